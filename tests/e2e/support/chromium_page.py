#!/usr/bin/env python3
"""Drives Debian's headless Chromium over its DevTools protocol for the status page's tests
and screenshots. Standard library only: the protocol runs over --remote-debugging-pipe
(file descriptors 3 and 4, JSON messages ended by a NUL byte), so no websocket module and no
driver package is needed.

    chromium_page.py check URL GATEWAY_PID   the live page test (tests/e2e/status_page_test.sh)
    chromium_page.py screenshot URL OUT.png WIDTH HEIGHT [SENSOR]
    chromium_page.py console URL OPERATOR VIEWER SENSOR SETTING
        the console test (tests/e2e/console_page_test.sh): OPERATOR and VIEWER are NAME:PASSWORD
    chromium_page.py confirm URL ADMIN   the apply's confirmation window in the Configuration tab
        (tests/e2e/console_confirm_page_test.sh): a countdown, then Confirm
    chromium_page.py counters URL ADMIN FAILING   the counters in the page
        (tests/e2e/console_counters_test.py): FAILING, a sensor nobody answers for, is red with
        errors in the last 10 min; each bus's table on the Buses tab; its reset, confirmed
    chromium_page.py monitoring URL ADMIN SENSOR   the monitoring in the page
        (tests/e2e/console_monitoring_test.py): the clock in the header, SENSOR's baseline set
        from its panel, its graph zoomed to an hour of the long record
    chromium_page.py forms URL ADMIN SENSOR FREE_UNIT   the guided configuration
        (tests/e2e/config_forms_test.py): SENSOR added with the Add a sensor form, applied and
        confirmed; an Edit form's change
    chromium_page.py walkthrough URL OPERATOR ADMIN SENSOR OUT_PREFIX   docs/web-console.md's
        "Try it" on `tiltgate demo`: OUT_PREFIX-{login,zero,counters,scan,add,apply,audit}.png
        (1280x800)
    chromium_page.py tabs URL ADMIN OUT_PREFIX SENSOR   a screenshot of each console tab,
        OUT_PREFIX-TAB.png (1280x800), OUT_PREFIX-phone[-sensor].png (390x844)
"""
import base64
import json
import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import urllib.request


CSP_WATCH = """document.addEventListener('securitypolicyviolation', (e) => {
  const seen = JSON.parse(sessionStorage.getItem('csp-violations') || '[]');
  seen.push(e.violatedDirective + ' ' + (e.blockedURI || 'inline') + ' ' + (e.sample || ''));
  sessionStorage.setItem('csp-violations', JSON.stringify(seen));
});"""


class Chromium:
    def __init__(self, width=1280, height=800):
        self.binary = shutil.which("chromium") or shutil.which("chromium-browser")
        if not self.binary:
            raise SystemExit("FAIL: chromium not found (Debian package chromium). Run scripts/setup.")
        self.profile = tempfile.mkdtemp(prefix="tiltgate-chromium-")
        to_browser_r, self.to_browser = os.pipe()
        self.from_browser, from_browser_w = os.pipe()

        def give_pipes():  # the browser reads fd 3 and writes fd 4
            read_end, write_end = os.dup(to_browser_r), os.dup(from_browser_w)
            os.dup2(read_end, 3)
            os.dup2(write_end, 4)

        args = [self.binary, "--headless", "--no-sandbox", "--disable-gpu",
                "--remote-debugging-pipe", "--user-data-dir=" + self.profile,
                "--no-first-run", "--no-default-browser-check", "--disable-extensions",
                "--hide-scrollbars", "--force-color-profile=srgb",
                "--window-size=%d,%d" % (width, height), "about:blank"]
        self.process = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                        stderr=subprocess.DEVNULL, preexec_fn=give_pipes,
                                        # os.pipe()'s and os.dup()'s descriptors are not
                                        # inherited (PEP 446); only 3 and 4 are.
                                        close_fds=False)
        os.close(to_browser_r)
        os.close(from_browser_w)
        self.buffer = b""
        self.next_id = 0
        self.session = None

    def close(self):
        try:
            self.send("Browser.close", session=False, wait=2)
        except Exception:
            pass
        try:
            self.process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        for fd in (self.to_browser, self.from_browser):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self.profile, ignore_errors=True)

    def send(self, method, params=None, session=True, wait=15):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            message["sessionId"] = self.session
        os.write(self.to_browser, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + wait
        while True:
            while b"\0" in self.buffer:
                raw, self.buffer = self.buffer.split(b"\0", 1)
                reply = json.loads(raw)
                if reply.get("id") == self.next_id:
                    if "error" in reply:
                        raise RuntimeError("%s: %s" % (method, reply["error"]))
                    return reply.get("result", {})
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("no answer to " + method)
            ready, _, _ = select.select([self.from_browser], [], [], left)
            if ready:
                chunk = os.read(self.from_browser, 1 << 16)
                if not chunk:
                    raise RuntimeError("chromium closed its pipe")
                self.buffer += chunk

    def open(self, url, width, height):
        target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.send("Target.attachToTarget",
                                 {"targetId": target, "flatten": True})["sessionId"]
        self.send("Emulation.setDeviceMetricsOverride",
                  {"width": width, "height": height, "deviceScaleFactor": 1,
                   "mobile": width < 600})
        # What the page's Content-Security-Policy blocked (an inline script or style, a style
        # attribute, a request elsewhere), kept across reloads of the tab: the page must need
        # nothing the policy refuses (docs/web-console.md, "Headers and host names").
        self.send("Page.enable", {})
        self.send("Page.addScriptToEvaluateOnNewDocument", {"source": CSP_WATCH})
        self.send("Page.navigate", {"url": url})

    def csp_violations(self):
        return self.evaluate("JSON.parse(sessionStorage.getItem('csp-violations') || '[]')")

    def evaluate(self, expression):
        result = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True})
        if "exceptionDetails" in result:
            return None
        return result["result"].get("value")

    def run(self, statement):
        """Runs JavaScript statements for their effect (a click, a field's value)."""
        self.evaluate("(() => { %s })()" % statement)

    def fill(self, selector, value):
        self.run("const e = document.querySelector(%s); e.value = %s; "
                 "e.dispatchEvent(new Event('input', {bubbles: true}));" %
                 (json.dumps(selector), json.dumps(value)))

    def click(self, selector):
        self.run("document.querySelector(%s).click();" % json.dumps(selector))

    def shoot(self, out):
        shot = self.send("Page.captureScreenshot", {"format": "png"})
        with open(out, "wb") as f:
            f.write(base64.b64decode(shot["data"]))

    def wait_for(self, expression, limit):
        """Polls `expression` until it is truthy; its last value, or None after `limit` s."""
        deadline = time.monotonic() + limit
        while time.monotonic() < deadline:
            value = self.evaluate(expression)
            if value:
                return value
            time.sleep(0.2)
        return None


# The page's state as the tests read it: the update counter, every sensor card's angle text
# and how often it changed, and the banner.
PAGE_STATE = """(() => ({
  updates: Number(document.body.dataset.updates || 0),
  state: document.body.dataset.state,
  banner: document.getElementById('banner').hidden ? '' : document.getElementById('banner').textContent,
  cards: [...document.querySelectorAll('.card')].map(c => ({
    name: c.dataset.name, x: c.querySelector('.value.x').textContent,
    changes: Number(c.dataset.changes), state: c.className }))
}))()"""


def api_sensor_names(url):
    with urllib.request.urlopen(url.rstrip("/") + "/api/sensors", timeout=5) as reply:
        return [s["name"] for s in json.load(reply)]


def check(url, gateway_pid):
    failures = []
    names = api_sensor_names(url)
    browser = Chromium()
    try:
        browser.open(url, 1280, 800)
        # Every sensor has a card with an angle in degrees.
        def all_angles():
            page = browser.evaluate(PAGE_STATE)
            cards = {c["name"]: c for c in page["cards"]} if page else {}
            ready = page and page["updates"] >= 2 and all(
                n in cards and cards[n]["x"].endswith("\u00b0") for n in names)
            return page if ready else None
        deadline = time.monotonic() + 15
        page = None
        while time.monotonic() < deadline and not page:
            page = all_angles()
            time.sleep(0.2)
        if not page:
            print("FAIL: not every sensor shows an angle: %s" % browser.evaluate(PAGE_STATE))
            return 1
        print("page: %d sensor cards with angles, %d updates" % (len(page["cards"]), page["updates"]))
        # ...and they change while the page stays open: every sensor's card counted changes of
        # its own (the demo's sensors all sway), and the page updated itself.
        first = browser.evaluate(PAGE_STATE)
        earlier = {c["name"]: c["changes"] for c in first["cards"]}
        deadline = time.monotonic() + 15
        while True:
            time.sleep(0.3)
            page = browser.evaluate(PAGE_STATE)
            cards = {c["name"]: c for c in page["cards"]}
            unchanged = [n for n in names
                         if cards.get(n, {}).get("changes", 0) <= earlier.get(n, 0)]
            if (not unchanged and page["updates"] > first["updates"]) or \
                    time.monotonic() > deadline:
                break
        if unchanged or page["updates"] <= first["updates"]:
            failures.append("the page did not follow the changing angles (unchanged on the "
                            "page: %s): %s" % (unchanged, page))
        else:
            print("page: %d updates; the angles of every sensor (%s) changed on the page" %
                  (page["updates"], ", ".join(names)))
        blocked = browser.csp_violations()
        if blocked != []:
            failures.append("the Content-Security-Policy blocked: %s" % blocked)
        else:
            print("page: the Content-Security-Policy blocked nothing")
        # The gateway goes away: the banner says so.
        os.kill(gateway_pid, signal.SIGKILL)
        banner = browser.wait_for(
            "document.body.dataset.state === 'unreachable' && "
            "!document.getElementById('banner').hidden && "
            "document.getElementById('banner').textContent", 15)
        if not banner or "unreachable since" not in banner.lower():
            failures.append("no unreachable banner after the gateway was killed: %s" %
                            browser.evaluate(PAGE_STATE))
        else:
            print("page: banner: " + banner)
    finally:
        browser.close()
    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


def screenshot(url, out, width, height, sensor=None):
    browser = Chromium(width, height)
    try:
        browser.open(url, width, height)
        # Real updates, long enough for the page's own polls/s figures (2 s windows).
        if not browser.wait_for("Number(document.body.dataset.updates) >= 12", 20):
            raise SystemExit("the page did not update")
        if sensor:
            browser.evaluate("document.querySelector('.card[data-name=\"%s\"]').click()" % sensor)
            browser.wait_for("document.querySelector('#detail-graph svg') !== null", 10)
        browser.shoot(out)
    finally:
        browser.close()
    return 0


# ---- the console (accounts): its login form, a sensor's settings, the tabs ----
def visible(selector):
    return ("(() => { const e = document.querySelector(%s); "
            "return !!e && e.offsetParent !== null; })()" % json.dumps(selector))


def log_in(browser, account, limit=15):
    """Logs in through the page's form; the header's user and role, or None."""
    user, password = account.split(":", 1)
    if not browser.wait_for(visible("#login-user"), limit):
        return None
    browser.fill("#login-user", user)
    browser.fill("#login-password", password)
    browser.click("#login-submit")
    return browser.wait_for(
        "!document.getElementById('who').hidden && document.getElementById('who-name').textContent === %s"
        " && document.getElementById('who-role').textContent" % json.dumps(user), limit)


def open_sensor(browser, sensor, limit=20):
    """Opens a sensor's card once the page shows it; its settings' names once read, or None."""
    card = '.card[data-name="%s"]' % sensor
    if not browser.wait_for("document.querySelector(%s) !== null" % json.dumps(card), limit):
        return None
    browser.click(card)
    return browser.wait_for(
        "(() => { const rows = [...document.querySelectorAll('#detail-settings tr[data-setting]')];"
        " return rows.length ? rows.map(r => r.dataset.setting) : null; })()", limit)


ENABLED_ACTIONS = """[...document.querySelectorAll(
  '#detail-settings button, main button[data-needs], main .scan, #scans button, #raw-send,'
  + ' #config-apply, #config-check')]
  .filter(b => !b.disabled && !b.hidden && b.offsetParent !== null).map(b => b.textContent)"""


def console_check(url, operator, viewer, sensor, setting):
    failures = []
    browser = Chromium()
    try:
        browser.open(url, 1280, 800)
        role = log_in(browser, operator)
        if role != "operator":
            print("FAIL: the operator's login through the form: role %r, form says %r" %
                  (role, browser.evaluate("document.getElementById('login-message').textContent")))
            return 1
        print("console: logged in as %s (%s)" % (operator.split(":")[0], role))
        names = open_sensor(browser, sensor)
        if not names:
            print("FAIL: no settings read from %s: %s" % (
                sensor, browser.evaluate("document.getElementById('detail-message').textContent")))
            return 1
        chosen = next((n for n in names if n == setting), None) or \
            next((n for n in names if n.startswith(setting)), None)
        if not chosen:
            print("FAIL: %s names no setting %s...: %s" % (sensor, setting, names))
            return 1
        row = '#detail-settings tr[data-setting="%s"]' % chosen
        # A range setting gets 0 (a zero offset); an action (one value) is its button alone.
        browser.run("const i = document.querySelector(%s); if (i) i.value = '0';" %
                    json.dumps(row + " input"))
        browser.click(row + " button")
        question = browser.wait_for(
            "!document.getElementById('confirm').hidden && "
            "document.getElementById('confirm-text').textContent", 5)
        if not question or sensor not in question or chosen not in question:
            failures.append("the confirmation does not name %s and %s: %r" % (sensor, chosen, question))
        else:
            print("console: asked: " + question)
        browser.click("#confirm-ok")
        result = browser.wait_for("document.body.dataset.lastResult", 20)
        message = browser.evaluate("document.getElementById('detail-message').textContent")
        if result != "ack":
            failures.append("%s of %s: %r (%s)" % (chosen, sensor, result, message))
        else:
            print("console: " + message)
        # Each setting shows its label with its key beneath, and where its value comes from: a
        # Rieker reads no setting back, so each is what was last written through the gateway.
        # (The rows are read again after the change: wait for them.)
        shown = browser.wait_for(
            "(() => { const r = document.querySelector(%s); return r ? [r.querySelector('b').textContent,"
            " r.querySelector('.key').textContent, r.querySelector('.value-cell').textContent] : null; })()"
            % json.dumps(row), 10)
        if not shown or shown[0] == chosen or shown[1] != chosen or \
                "last written through this gateway" not in shown[2]:
            failures.append("%s's row should show its label, the key %s beneath and "
                            "'last written through this gateway': %r" % (chosen, chosen, shown))
        heading = browser.evaluate("document.querySelector('#detail-console h4').textContent")
        if "read from the sensor" in heading:
            failures.append("the settings' heading claims every value is read from the sensor: %r"
                            % heading)
        # A Rieker's command is its actions, named by what they do: the operator may zero (1, 2)
        # but not restart (3), and the question says what the action does to which sensor.
        command = '#detail-settings tr[data-setting="command"]'
        if "command" in names:
            buttons = browser.wait_for(
                "(() => { const b = [...document.querySelectorAll(%s)]"
                ".map(b => [b.textContent, b.disabled]); return b.length ? b : null; })()"
                % json.dumps(command + " button"), 10)
            expected = [["Zero to the current angle (until restart)", False],
                        ["Zero permanently", False], ["Restart the sensor", True]]
            if buttons != expected:
                failures.append("the operator's command row: %r, expected %r" % (buttons, expected))
            else:
                browser.run("delete document.body.dataset.lastResult")
                browser.run("[...document.querySelectorAll(%s)].find(b => b.textContent === "
                            "'Zero to the current angle (until restart)').click()"
                            % json.dumps(command + " button"))
                question = browser.wait_for(
                    "!document.getElementById('confirm').hidden && "
                    "document.getElementById('confirm-text').textContent", 5)
                wanted = "Zero %s to its current angle? Until the sensor restarts." % sensor
                if question != wanted:
                    failures.append("the zero's question: %r, expected %r" % (question, wanted))
                else:
                    print("console: asked: " + question)
                browser.click("#confirm-ok")
                zeroed = browser.wait_for("document.body.dataset.lastResult", 20)
                if zeroed != "ack":
                    failures.append("Zero to the current angle (until restart): %r (%s)" % (
                        zeroed, browser.evaluate(
                            "document.getElementById('detail-message').textContent")))
                else:
                    print("console: the operator zeroed to the current angle: " + browser.evaluate(
                        "document.getElementById('detail-message').textContent"))
        # The Audit tab shows the change: who, sensor, setting, result.
        browser.click("#detail-close")
        browser.click('.tab[data-tab="audit"]')
        user = operator.split(":")[0]
        record = browser.wait_for(
            "[...document.querySelectorAll('#audit-table tbody tr')].map(r =>"
            " Object.fromEntries([...r.cells].map(c => [c.dataset.key, c.textContent])))"
            ".find(r => r.who === %s && (r.sensor === %s || r.sensor.endsWith('/' + %s))"
            " && r.setting === %s)" %
            (json.dumps(user), json.dumps(sensor), json.dumps(sensor), json.dumps(chosen)), 10)
        if not record:
            failures.append("no audit record of %s's %s on %s in the Audit tab: %s" % (
                user, chosen, sensor, browser.evaluate(
                    "document.querySelector('#audit-table tbody').textContent")))
        else:
            print("console: audit record: %s" % record)
        # Log out: the form again; then the viewer sees no enabled action anywhere.
        browser.click("#logout")
        if not browser.wait_for(visible("#login-user"), 10):
            failures.append("no login form after logging out")
        role = log_in(browser, viewer)
        if role != "viewer":
            failures.append("the viewer's login: role %r" % role)
        else:
            if not open_sensor(browser, sensor):
                failures.append("the viewer sees no settings of %s" % sensor)
            enabled = browser.evaluate(ENABLED_ACTIONS)
            browser.click("#detail-close")
            for tab in ("buses", "audit"):
                browser.click('.tab[data-tab="%s"]' % tab)
                time.sleep(0.5)
                enabled = (enabled or []) + (browser.evaluate(ENABLED_ACTIONS) or [])
            admin_tabs = browser.evaluate(
                "[...document.querySelectorAll('.tab[data-needs]')].filter(t => !t.hidden)"
                ".map(t => t.textContent)")
            if enabled or admin_tabs:
                failures.append("the viewer has enabled actions %s, tabs %s" % (enabled, admin_tabs))
            else:
                print("console: the viewer sees the settings with no enabled action and no admin tab")
        blocked = browser.csp_violations()
        if blocked != []:
            failures.append("the Content-Security-Policy blocked: %s" % blocked)
        else:
            print("console: the Content-Security-Policy blocked nothing")
    finally:
        browser.close()
    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


def confirm_check(url, admin):
    """Apply an edit in the Configuration tab: the page counts the window down; Confirm keeps it."""
    browser = Chromium()
    try:
        browser.open(url, 1280, 800)
        if log_in(browser, admin) != "admin":
            print("FAIL: the admin could not log in")
            return 1
        browser.click('.tab[data-tab="config"]')
        if not browser.wait_for("document.getElementById('editor').value !== ''", 10):
            print("FAIL: the Configuration tab shows no file")
            return 1
        browser.run("const e = document.getElementById('editor');"
                    "e.value = '# edited through the page\\n' + e.value;")
        browser.click("#config-apply")
        if not browser.wait_for("!document.getElementById('confirm').hidden", 5):
            print("FAIL: Apply asked nothing")
            return 1
        browser.click("#confirm-ok")
        countdown = browser.wait_for(
            "!document.getElementById('config-pending').hidden && "
            "!document.getElementById('config-confirm').hidden && "
            "/comes back in \\d+ s/.test(document.getElementById('config-pending-text').textContent) && "
            "document.getElementById('config-pending-text').textContent", 15)
        if not countdown:
            print("FAIL: no countdown after the apply: %r" % browser.evaluate(
                "document.getElementById('config-message').textContent"))
            return 1
        print("confirm: " + countdown)
        browser.click("#config-confirm")
        confirmed = browser.wait_for(
            "document.getElementById('config-pending').hidden && "
            "/Confirmed/.test(document.getElementById('config-message').textContent)", 15)
        if not confirmed:
            # Too early (the gateway had not reloaded yet): the page says so; once more.
            time.sleep(2)
            browser.click("#config-confirm")
            confirmed = browser.wait_for(
                "document.getElementById('config-pending').hidden && "
                "/Confirmed/.test(document.getElementById('config-message').textContent)", 15)
        if not confirmed:
            print("FAIL: Confirm did not confirm: %r" % browser.evaluate(
                "document.getElementById('config-message').textContent"))
            return 1
        print("confirm: confirmed through the page")
    finally:
        browser.close()
    return 0


def counters_check(url, admin, failing):
    failures = []
    browser = Chromium()
    try:
        browser.open(url, 1280, 800)
        if log_in(browser, admin) != "admin":
            raise SystemExit("FAIL: the admin could not log in")
        errors = '.card[data-name="%s"] .errors' % failing
        seen = browser.wait_for(
            "(() => { const e = document.querySelector(%s);"
            " return e && e.textContent.includes('in 10 min') && e.classList.contains('bad')"
            " && e.className; })()" %
            json.dumps(errors), 20)
        if not seen or "bad" not in seen:
            failures.append("the failing sensor's card does not show its errors of the last "
                            "10 min in red: %r" % browser.evaluate(
                                "document.querySelector(%s)?.outerHTML" % json.dumps(errors)))
        browser.click('.tab[data-tab="buses"]')
        rows = browser.wait_for(
            "(() => { const t = document.querySelector('#scans .bus-counters table.counters');"
            " return t ? [...t.querySelectorAll('tbody tr td:first-child')].map(c => c.textContent)"
            " : null; })()", 10)
        if not rows or "time-outs" not in rows or "polls" not in rows:
            failures.append("the Buses tab has no counters table: %r" % rows)
        hint = browser.wait_for(
            "(() => { const h = document.querySelector('#scans .hint');"
            " return h && !h.hidden && h.textContent; })()", 10)
        if not hint or not hint.startswith(failing + " does not answer"):
            failures.append("the Buses tab shows no hint naming %s: %r" % (failing, hint))
        health = browser.wait_for(
            "(() => { const r = [...document.querySelectorAll('#scans .line-health tbody tr')]"
            "  .find(r => r.cells[0].textContent === %s);"
            " return r && [...r.cells].map(c => c.className + ':' + c.textContent); })()" %
            json.dumps(failing), 10)
        if not health or not any(c.endswith("bad") or " bad:" in c for c in health):
            failures.append("the line health table has no red row for %s: %r" % (failing, health))
        browser.click("#scans .reset")
        if not browser.wait_for("!document.getElementById('confirm').hidden", 5):
            failures.append("Reset counters asks for no confirmation")
        asked = browser.evaluate("document.getElementById('confirm-text').textContent")
        browser.click("#confirm-ok")
        said = browser.wait_for(
            "document.querySelector('#scans .counters-message').textContent", 10)
        if not said or "reset" not in said:
            failures.append("the reset says nothing: asked %r, said %r" % (asked, said))
        print("counters page: asked %r, said %r" % (asked, said))
    finally:
        browser.close()
    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


def monitoring_check(url, admin, sensor):
    """The clock in the header; the admin sets the sensor's baseline from its panel, with a
    confirmation; its graph zooms from the recent minutes to an hour of the long record."""
    failures = []
    browser = Chromium()
    try:
        browser.open(url, 1280, 800)
        if log_in(browser, admin) != "admin":
            raise SystemExit("FAIL: the admin could not log in")
        clock = browser.wait_for(
            "(() => { const c = document.getElementById('clock');"
            " return c && !c.hidden && c.textContent; })()", 20)
        if not clock or not clock.startswith("clock "):
            failures.append("the header does not say the clock: %r" % clock)
        if open_sensor(browser, sensor) is None:
            raise SystemExit("FAIL: the sensor's panel did not open")
        shown = browser.wait_for(
            "(() => { const t = document.getElementById('detail-baseline').textContent;"
            " return t.includes('configuration') && t; })()", 10)
        if not shown:
            failures.append("the panel does not show the configuration's baseline: %r" %
                            browser.evaluate("document.getElementById('detail-baseline').textContent"))
        browser.click("#detail-baseline-set")
        if not browser.wait_for("!document.getElementById('confirm').hidden", 5):
            failures.append("Set to the current reading asks for no confirmation")
        browser.click("#confirm-ok")
        said = browser.wait_for(
            "(() => { const t = document.getElementById('baseline-message').textContent;"
            " return t.startsWith('Baseline set') && t; })()", 10)
        now = browser.evaluate("document.getElementById('detail-baseline').textContent")
        if not said or "set by console " + admin.split(":")[0] not in (now or ""):
            failures.append("the baseline change says nothing, or not who: %r, %r" % (said, now))
        live = browser.wait_for(
            "document.querySelector('#detail-graph svg path.line.x') !== null", 15)
        if not live:
            failures.append("the recent graph has no X line")
        browser.click('#detail-zoom button[data-span="3600000"]')
        zoomed = browser.wait_for(
            "(() => { const r = document.getElementById('detail-range').textContent;"
            " return r.includes('long record') &&"
            " document.querySelector('#detail-graph svg path.line.x') !== null && r; })()", 15)
        if not zoomed:
            failures.append("the hour's graph of the long record did not draw: %r" %
                            browser.evaluate("document.getElementById('detail-graph').innerHTML.slice(0, 300)"))
        pressed = browser.evaluate(
            "document.querySelector('#detail-zoom button[data-span=\"3600000\"]').getAttribute('aria-pressed')")
        link = browser.evaluate("document.getElementById('detail-csv').getAttribute('href')")
        if pressed != "true" or "from=" not in (link or "") or "points=" in (link or ""):
            failures.append("the zoom button is not pressed, or the CSV link is not the record's "
                            "whole range: %r, %r" % (pressed, link))
        print("monitoring page: clock %r, baseline %r, graph %r" % (clock, now, zoomed))
    finally:
        browser.close()
    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


def forms_check(url, admin, sensor, free_unit):
    """Guided configuration (tests/e2e/config_forms_test.py): the admin adds SENSOR with the
    Add a sensor form, first with a unit id another sensor has (its error at the field), then
    FREE_UNIT; the form's text goes into the editor, the editor's Apply shows the diff, applies
    and confirms; then changes boom's poll_ms with its Edit form."""
    failures = []
    browser = Chromium()
    try:
        browser.open(url, 1280, 900)
        if log_in(browser, admin) != "admin":
            raise SystemExit("FAIL: the admin could not log in")
        browser.click('.tab[data-tab="config"]')
        if not browser.wait_for("document.querySelectorAll('#forms-tables tbody tr').length >= 3", 15):
            failures.append("the Configuration tab lists no buses and sensors: %r" % browser.evaluate(
                "document.getElementById('forms').innerText"))
        browser.click("#form-add-sensor")
        if not browser.wait_for("!document.getElementById('table-form').hidden", 10):
            failures.append("Add a sensor opens no form")
        proposed = browser.evaluate("document.getElementById('field-unit_id').value")
        if proposed != str(free_unit):
            failures.append("the form proposes unit id %r, not the free %d" % (proposed, free_unit))
        buses = browser.evaluate("[...document.querySelectorAll('#field-bus option')].map(o => o.value)")
        if not buses or "line1" not in buses:
            failures.append("the bus field does not offer the text's buses: %r" % buses)
        browser.fill("#field-name", sensor)
        browser.fill("#field-bus", "line1")
        browser.fill("#field-model", "h6")
        browser.fill("#field-address", "58")
        browser.fill("#field-unit_id", "1")
        browser.click("#table-form-submit")
        error = browser.wait_for("document.querySelector('.field[data-field=\"unit_id\"] .field-error')"
                                 ".textContent", 10)
        if not error or "boom" not in error:
            failures.append("a taken unit id shows no error at its field: %r" % error)
        browser.fill("#field-unit_id", str(free_unit))
        browser.click("#table-form-submit")
        if not browser.wait_for("document.getElementById('table-form').hidden && "
                                "document.getElementById('editor').value.includes('name = \"%s\"')"
                                % sensor, 10):
            failures.append("the valid form's text is not in the editor: %r" % browser.evaluate(
                "document.getElementById('table-form').innerText"))
        said = browser.evaluate("document.getElementById('forms-message').textContent")
        if not said or "Apply" not in said:
            failures.append("the form says nothing of what to do next: %r" % said)
        if browser.evaluate("document.getElementById('config-pending').offsetParent !== null || "
                            "document.getElementById('config-confirm-link').offsetParent !== null"):
            failures.append("Confirm shows while nothing awaits confirmation")
        browser.click("#config-apply")
        if not browser.wait_for("!document.getElementById('confirm').hidden", 5):
            failures.append("Apply asks for no confirmation")
        diff = browser.evaluate("document.getElementById('confirm-detail').textContent") or ""
        if "+ [[sensor]]" not in diff or ("+ name = \"%s\"" % sensor) not in diff:
            failures.append("the apply's confirmation shows no diff of the form's table: %r" % diff)
        browser.click("#confirm-ok")
        if not browser.wait_for("!document.getElementById('config-pending').hidden", 15):
            failures.append("the apply awaits no confirmation: %r" % browser.evaluate(
                "document.getElementById('config-message').textContent"))
        browser.click("#config-confirm")
        confirmed = browser.wait_for(
            "document.getElementById('config-message').textContent.startsWith('Confirmed')", 15)
        if not confirmed:
            failures.append("the applied text is not confirmed: %r" % browser.evaluate(
                "document.getElementById('config-message').textContent"))
        browser.wait_for("document.querySelector('#forms-tables tr[data-name=\"%s\"]')" % sensor, 10)
        browser.click('#forms-tables tr[data-name="boom"] button.edit')
        if not browser.wait_for("!document.getElementById('table-form').hidden && "
                                "document.getElementById('field-address').value !== ''", 10):
            failures.append("Edit opens no form filled with boom's values")
        browser.fill("#field-poll_ms", "250")
        browser.click("#table-form-submit")
        if not browser.wait_for("document.getElementById('editor').value.includes('poll_ms = 250')", 10):
            failures.append("the Edit form's change is not in the editor")
        print("forms page: %s" % said)
    finally:
        browser.close()
    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


# The zero's button: by its action name, else (before actions had names) by its value.
ZERO_BUTTON = """(() => { const b = [...document.querySelectorAll('#detail-settings button')]
  .find(b => b.textContent.startsWith('Zero to the current angle')
             || b.getAttribute('aria-label') === 'write 1 to command');
  if (b) b.click(); return !!b; })()"""


def walkthrough(url, operator, admin, sensor, prefix):
    """docs/web-console.md, "Try it", step by step, a screenshot of each."""
    browser = Chromium(1280, 800)
    try:
        browser.open(url, 1280, 800)
        if not browser.wait_for(visible("#login-user"), 15):
            raise SystemExit("no login form at " + url)
        browser.fill("#login-user", operator.split(":")[0])
        browser.shoot(prefix + "-login.png")
        if log_in(browser, operator) != "operator":
            raise SystemExit("the operator could not log in")
        browser.wait_for("Number(document.body.dataset.updates) >= 4", 20)
        if not open_sensor(browser, sensor):
            raise SystemExit("no settings for " + sensor)
        if not browser.evaluate(ZERO_BUTTON):
            raise SystemExit("no zero button for " + sensor)
        browser.wait_for("!document.getElementById('confirm').hidden", 5)
        browser.click("#confirm-ok")
        browser.wait_for("document.body.dataset.lastResult", 20)
        time.sleep(1)
        browser.shoot(prefix + "-zero.png")
        browser.click("#detail-close")
        browser.click("#logout")
        if log_in(browser, admin) != "admin":
            raise SystemExit("the admin could not log in")
        browser.click('.tab[data-tab="buses"]')
        browser.wait_for("document.querySelector('#scans table.counters') !== null", 10)
        browser.shoot(prefix + "-counters.png")
        # Scan demo-bus around its sensors: boom-tip, fitted at 225, is not configured.
        form = "#scans form[data-bus=\"demo-bus\"]"
        browser.run("const f = document.querySelector(%s);"
                    "f.querySelector('.from').value = 220; f.querySelector('.to').value = 230;"
                    "f.querySelector('.scan').click();" % json.dumps(form))
        browser.wait_for("document.querySelector(%s).dataset.running === 'false' && "
                         "[...document.querySelectorAll(%s)].some(b => b.textContent === "
                         "'Add to the configuration')" % (json.dumps(form), json.dumps(form + " button")), 60)
        browser.run("document.querySelector(%s).scrollIntoView()" % json.dumps(form))
        browser.shoot(prefix + "-scan.png")
        browser.evaluate("[...document.querySelectorAll(%s)].find(b => b.textContent === "
                         "'Add to the configuration').click()" % json.dumps(form + " button"))
        if not browser.wait_for("!document.getElementById('table-form').hidden", 10):
            raise SystemExit("Add to the configuration opens no form")
        browser.fill("#field-name", "boom-tip")
        browser.shoot(prefix + "-add.png")
        browser.click("#table-form-submit")
        if not browser.wait_for("document.getElementById('table-form').hidden", 10):
            raise SystemExit("the scan's sensor does not go into the editor")
        browser.click("#config-apply")
        browser.wait_for("!document.getElementById('confirm').hidden", 5)
        browser.shoot(prefix + "-apply.png")
        browser.click("#confirm-ok")
        browser.wait_for("!document.getElementById('config-pending').hidden", 15)
        browser.click("#config-confirm")
        browser.wait_for("document.getElementById('config-message').textContent"
                         ".startsWith('Confirmed')", 15)
        browser.click('.tab[data-tab="audit"]')
        browser.wait_for("document.querySelector('#audit-table tbody tr') !== null", 10)
        browser.shoot(prefix + "-audit.png")
    finally:
        browser.close()
    return 0


def tab_screenshots(url, admin, prefix, sensor):
    """The login form, then each tab in use, as the docs show them."""
    browser = Chromium(1280, 800)
    try:
        browser.open(url, 1280, 800)
        if not browser.wait_for(visible("#login-user"), 15):
            raise SystemExit("no login form at " + url)
        browser.fill("#login-user", admin.split(":")[0])
        browser.shoot(prefix + "-login.png")
        if log_in(browser, admin) != "admin":
            raise SystemExit("the admin could not log in")
        browser.wait_for("Number(document.body.dataset.updates) >= 12", 20)
        names = open_sensor(browser, sensor) or []
        # A zero through the console, so the sensor shows its answer and the Audit tab a record.
        zero = next((n for n in names if n.startswith("zero")), None)
        if zero:
            row = '#detail-settings tr[data-setting="%s"]' % zero
            browser.run("const i = document.querySelector(%s); if (i) i.value = '0';" %
                        json.dumps(row + " input"))
            browser.click(row + " button")
            browser.wait_for("!document.getElementById('confirm').hidden", 5)
            browser.click("#confirm-ok")
            browser.wait_for("document.body.dataset.lastResult", 20)
            browser.wait_for("document.querySelector('#detail-settings tr[data-setting]')", 10)
        browser.shoot(prefix + "-sensor.png")
        browser.click("#detail-close")
        browser.click('.tab[data-tab="buses"]')
        browser.wait_for("document.querySelector('#scans form') !== null", 5)
        browser.run("const f = document.querySelector('#scans form');"
                    "f.querySelector('.from').value = 1; f.querySelector('.to').value = 8;"
                    "f.querySelector('.scan').click();")
        browser.wait_for("document.querySelector('#scans form').dataset.running === 'false' && "
                         "document.querySelector('#scans .found, #scans .output')", 60)
        browser.shoot(prefix + "-buses.png")
        # A found sensor fills the Add a sensor form, whose text goes into the editor (the
        # Configuration tab's diff then shows it).
        added = browser.evaluate("(() => { const b = [...document.querySelectorAll('#scans button')]"
                                 ".find(b => b.textContent === 'Add to the configuration');"
                                 " if (b) b.click(); return !!b; })()")
        if added and browser.wait_for("!document.getElementById('table-form').hidden", 10):
            browser.click("#table-form-submit")
            browser.wait_for("document.getElementById('table-form').hidden", 10)
        browser.click('.tab[data-tab="raw"]')
        browser.click("#raw-send")
        browser.wait_for("!document.getElementById('raw-result').hidden", 10)
        browser.shoot(prefix + "-raw.png")
        browser.click('.tab[data-tab="config"]')
        browser.wait_for("document.getElementById('editor').value !== ''", 10)
        if not added:
            browser.run("const e = document.getElementById('editor');"
                        "e.value = e.value.replace(/poll_ms = \\d+/, 'poll_ms = 200');")
        browser.click("#config-diff")
        browser.shoot(prefix + "-config.png")
        browser.click('.tab[data-tab="audit"]')
        browser.wait_for("document.querySelector('#audit-table tbody tr') !== null", 10)
        browser.shoot(prefix + "-audit.png")
        browser.send("Emulation.setDeviceMetricsOverride",
                     {"width": 390, "height": 844, "deviceScaleFactor": 1, "mobile": True})
        browser.click('.tab[data-tab="sensors"]')
        time.sleep(1)
        browser.shoot(prefix + "-phone.png")
        open_sensor(browser, sensor)
        time.sleep(1)
        browser.shoot(prefix + "-phone-sensor.png")
    finally:
        browser.close()
    return 0


def main(argv):
    if len(argv) >= 4 and argv[1] == "check":
        return check(argv[2], int(argv[3]))
    if len(argv) >= 6 and argv[1] == "screenshot":
        return screenshot(argv[2], argv[3], int(argv[4]), int(argv[5]),
                          argv[6] if len(argv) > 6 else None)
    if len(argv) >= 7 and argv[1] == "console":
        return console_check(argv[2], argv[3], argv[4], argv[5], argv[6])
    if len(argv) >= 4 and argv[1] == "confirm":
        return confirm_check(argv[2], argv[3])
    if len(argv) >= 5 and argv[1] == "counters":
        return counters_check(argv[2], argv[3], argv[4])
    if len(argv) >= 5 and argv[1] == "monitoring":
        return monitoring_check(argv[2], argv[3], argv[4])
    if len(argv) >= 6 and argv[1] == "forms":
        return forms_check(argv[2], argv[3], argv[4], int(argv[5]))
    if len(argv) >= 7 and argv[1] == "walkthrough":
        return walkthrough(argv[2], argv[3], argv[4], argv[5], argv[6])
    if len(argv) >= 6 and argv[1] == "tabs":
        return tab_screenshots(argv[2], argv[3], argv[4], argv[5])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
