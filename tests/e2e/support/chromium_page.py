#!/usr/bin/env python3
"""Drives Debian's headless Chromium over its DevTools protocol for the status page's tests
and screenshots. Standard library only: the protocol runs over --remote-debugging-pipe
(file descriptors 3 and 4, JSON messages ended by a NUL byte), so no websocket module and no
driver package is needed.

    chromium_page.py check URL GATEWAY_PID   the live page test (tests/e2e/status_page_test.sh)
    chromium_page.py screenshot URL OUT.png WIDTH HEIGHT [SENSOR]
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
        self.send("Page.navigate", {"url": url})

    def evaluate(self, expression):
        result = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True})
        if "exceptionDetails" in result:
            return None
        return result["result"].get("value")

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
        shot = browser.send("Page.captureScreenshot", {"format": "png"})
        with open(out, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
    finally:
        browser.close()
    return 0


def main(argv):
    if len(argv) >= 4 and argv[1] == "check":
        return check(argv[2], int(argv[3]))
    if len(argv) >= 6 and argv[1] == "screenshot":
        return screenshot(argv[2], argv[3], int(argv[4]), int(argv[5]),
                          argv[6] if len(argv) > 6 else None)
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
