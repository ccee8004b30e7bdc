#!/usr/bin/env python3
"""The console's traffic view and black-box download (issue 55, items 5 and 6;
docs/web-console.md, "Traffic"): `tiltgate demo` with its accounts, read with Python's
http.client and driven in Debian's headless Chromium.

- As admin, GET /api/buses/NAME/frames lists the bus's requests and replies, numbered one by
  one, each reply with its request's address and function; after=next returns only newer ones.
- An operator gets 403, and the trail a refused record; viewing is one record per view
  started, never one per poll.
- GET /api/buses/NAME/capture.pcapng is a pcapng file (its magic 0A 0D 0D 0A) that Debian's
  tshark reads, the demo's Modbus RTU bus decoded as Modbus RTU; each download one audit record.
- In Chromium: the admin opens a bus's Traffic view and rows come; Pause stops them, Resume
  brings them again; the address filter hides the other devices' rows; on a phone's width the
  bytes show on a tap; an operator has no Traffic view.

Usage: /usr/bin/python3 console_traffic_test.py path/to/tiltgate
"""
import http.client
import json
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "support"))
sys.path.insert(0, os.path.join(HERE, "sparkplug"))
from console_api_test import Client  # noqa: E402
from demo_console_test import printed_accounts, start_demo  # noqa: E402
from chromium_page import Chromium, log_in, visible  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e import processes  # noqa: E402

RTU_BUS = "demo-rtu-bus"      # one Modbus RTU device, slave 1
RIEKER_BUS = "demo-bus"       # Rieker sensors at 101, 223 and 224
PCAPNG_MAGIC = bytes.fromhex("0A0D0D0A")


def download(client, path):
    """GET `path` as `client`, the body as bytes: (status, headers, body)."""
    connection = http.client.HTTPConnection("127.0.0.1", client.port, timeout=30)
    connection.request("GET", path, headers={"Cookie": "tiltgate_session=" + client.cookie})
    response = connection.getresponse()
    body = response.read()
    headers = {k.lower(): v for k, v in response.getheaders()}
    connection.close()
    return response.status, headers, body


def frames_of(client, bus, after=None):
    path = "/api/buses/%s/frames" % bus + ("" if after is None else "?after=%d" % after)
    return client.request("GET", path)


def audit(client, setting):
    status, body = client.request("GET", "/api/audit?door=console&setting=" + setting)
    return [(r["who"], r["sensor"], r["new"], r["result"]) for r in body.get("records", [])] \
        if status == 200 else []


def api_checks(t, admin, operator, work_dir):
    status, view = frames_of(admin, RTU_BUS)
    frames = view.get("frames", []) if status == 200 else []
    t.check("the admin's first look: the bus, its protocol, its newest frames, next and keep_s",
            status == 200 and view.get("bus") == RTU_BUS and view.get("protocol") == "modbus-rtu"
            and 0 < len(frames) <= 100 and view.get("next") == frames[-1]["n"] and
            view.get("missed") == 0 and view.get("keep_s") == 60,
            (status, {k: v for k, v in view.items() if k != "frames"} if status == 200 else view))
    numbers = [f["n"] for f in frames]
    t.check("frames are numbered one by one, oldest first",
            numbers == list(range(numbers[0], numbers[0] + len(numbers))) if numbers else False,
            numbers)
    requests = [f for f in frames if f["direction"] == "out"]
    replies = [f for f in frames if f["direction"] == "in"]
    t.check("requests to slave 1 with their function, read by the bus's protocol",
            requests and all(f["verdict"] == "request" and f["address"] == 1 and
                             re.match(r"function 0[34]$", f["function"] or "") for f in requests),
            requests[:3])
    t.check("replies with their request's address and function, their checksum's verdict, no "
            "refusal",
            replies and all(f["address"] == 1 and f["function"] and f["verdict"] == "CRC ok" and
                            f["refusal"] is None for f in replies[1:]), replies[:3])
    t.check("each reply's values, decoded by the bus's protocol as the answer to its request",
            replies and all(re.match(r"^values -?\d+(, -?\d+)*(, \.\.\.)?$", f["values"] or "")
                            for f in replies[1:]) and
            all(f["values"] is None for f in requests), replies[1:3])
    t.check("each frame: its time in microseconds, its bytes in hex, no 9-bit address bytes",
            all(isinstance(f["time_us"], int) and f["time_us"] > 1.7e15 and
                re.match(r"^([0-9A-F]{2} )*[0-9A-F]{2}$", f["bytes"]) and
                f["address_bytes"] == 0 for f in frames), frames[:2])

    last = view.get("next", 0)
    time.sleep(1)
    status, newer = frames_of(admin, RTU_BUS, last)
    got = [f["n"] for f in newer.get("frames", [])] if status == 200 else []
    t.check("after=next: only the frames since, from next + 1 on",
            status == 200 and got and got[0] == last + 1 and all(n > last for n in got) and
            newer["next"] == got[-1] and newer["missed"] == 0, (status, got[:5], last))
    status, same = frames_of(admin, RTU_BUS, newer.get("next", 0) + 10**9)
    t.check("an after past the newest (a bus made anew) starts the view over",
            status == 200 and same["frames"] and same["next"] < 10**9, (status, same.get("next")))

    status, body = admin.request("GET", "/api/buses/%s/frames?after=x1" % RTU_BUS)
    t.check("after that is no frame number: 400", status == 400, (status, body))
    status, body = frames_of(admin, "no-such-bus")
    t.check("a bus not served: 404", status == 404, (status, body))
    status, body = admin.request("POST", "/api/buses/%s/frames" % RTU_BUS, {})
    t.check("frames are read with GET: POST is 405", status == 405, (status, body))

    status, body = frames_of(operator, RTU_BUS)
    t.check("an operator's look: 403 saying why",
            status == 403 and body.get("error") == "the traffic view is for the admin role",
            (status, body))
    status, headers, body = download(operator, "/api/buses/%s/capture.pcapng" % RTU_BUS)
    t.check("an operator's download: 403", status == 403, (status, body[:200]))

    status, headers, body = download(admin, "/api/buses/%s/capture.pcapng" % RTU_BUS)
    disposition = headers.get("content-disposition", "")
    t.check("the admin's download: a pcapng file (magic 0A 0D 0D 0A), saved as "
            "tiltgate-BUS-YYYYmmdd-HHMMSS.pcapng",
            status == 200 and body.startswith(PCAPNG_MAGIC) and
            headers.get("content-type") == "application/octet-stream" and
            re.fullmatch(r'attachment; filename="tiltgate-%s-\d{8}-\d{6}\.pcapng"' % RTU_BUS,
                         disposition), (status, headers, body[:16]))
    path = os.path.join(work_dir, "capture.pcapng")
    with open(path, "wb") as f:
        f.write(body)
    read = subprocess.run(["/usr/bin/tshark", "-r", path], capture_output=True, text=True,
                          timeout=60)
    lines = [l for l in read.stdout.splitlines() if l.strip()]
    t.check("tshark reads it: the Modbus RTU bus's queries and responses decoded as Modbus RTU",
            read.returncode == 0 and len(lines) > 10 and
            all("Modbus RTU" in l for l in lines) and
            any("Query" in l for l in lines) and any("Response" in l for l in lines),
            (read.returncode, read.stderr[-500:], lines[:4]))

    # A read of a register the device does not have: its exception reply is a refusal.
    status, raw = admin.request("POST", "/api/buses/%s/raw" % RTU_BUS,
                                {"address": 1, "function": 3, "data": "FF 00 00 01"})
    status, after_raw = frames_of(admin, RTU_BUS, newer.get("next", 0))
    refused = [f for f in after_raw.get("frames", []) if f["refusal"]]
    t.check("a device's exception reply: its refusal, with its request's address and function",
            refused and refused[0]["refusal"] == "nak 0x02" and refused[0]["address"] == 1 and
            refused[0]["function"] == "function 03" and refused[0]["bytes"].startswith("01 83 02"),
            (raw, refused))

    captures = audit(admin, "capture")
    t.check("the download is one audit record: the bus, capture, last 60 s, ok, who; the refused "
            "one too",
            captures.count(("admin", RTU_BUS, "last 60 s", "ok")) == 1 and
            ("operator", RTU_BUS, "download", "refused: a capture is for the admin role")
            in captures, captures)
    watches = audit(admin, "traffic")
    t.check("the looks: one record per view started (not per poll), and the refused one",
            watches.count(("admin", RTU_BUS, "watch", "ok")) == 1 and
            ("operator", RTU_BUS, "watch", "refused: the traffic view is for the admin role")
            in watches, watches)


# ---- in Chromium ----
def panel(bus):
    return '#scans form[data-bus="%s"] details.traffic' % bus


def rows_js(bus):
    """The shown rows' numbers and addresses, newest first."""
    return ("[...document.querySelectorAll(%s)].filter(r => !r.hidden)"
            ".map(r => [Number(r.dataset.n), r.dataset.address])"
            % json.dumps(panel(bus) + " tbody tr[data-n]"))


def browser_checks(t, url, admin, operator, admin_api):
    """`admin_api`: the admin's API client, for a raw frame while the page watches."""
    browser = Chromium()
    try:
        browser.open(url, 1280, 900)
        t.check("in Chromium: the admin logs in", log_in(browser, admin) == "admin")
        browser.click('.tab[data-tab="buses"]')
        browser.wait_for("document.querySelector(%s) !== null" % json.dumps(panel(RIEKER_BUS)), 15)
        t.check("each bus's panel has a Traffic view for the admin",
                browser.evaluate(visible(panel(RIEKER_BUS) + " summary")))
        browser.run("document.querySelector(%s).open = true" % json.dumps(panel(RIEKER_BUS)))
        rows = browser.wait_for("(() => { const r = %s; return r.length >= 10 ? r : null; })()"
                                % rows_js(RIEKER_BUS), 15)
        t.check("opened, it lists the bus's frames, newest first",
                rows and all(a[0] > b[0] for a, b in zip(rows, rows[1:])), rows and rows[:5])
        more = browser.wait_for("(() => { const r = %s; return r.length && r[0][0] > %d ? r : null; })()"
                                % (rows_js(RIEKER_BUS), rows[0][0] if rows else 0), 10)
        t.check("new frames come while it is open", bool(more))

        browser.click(panel(RIEKER_BUS) + " .traffic-pause")
        time.sleep(0.8)   # a poll that was under way when Pause was pressed lands or is dropped
        paused = browser.evaluate(rows_js(RIEKER_BUS))
        time.sleep(1.5)
        still = browser.evaluate(rows_js(RIEKER_BUS))
        t.check("Pause stops new rows", paused and still and paused[0] == still[0] and
                browser.evaluate("document.querySelector(%s).textContent" %
                                 json.dumps(panel(RIEKER_BUS) + " .traffic-pause")) == "Resume",
                (paused and paused[0], still and still[0]))
        browser.click(panel(RIEKER_BUS) + " .traffic-pause")
        resumed = browser.wait_for("(() => { const r = %s; return r.length && r[0][0] > %d; })()"
                                   % (rows_js(RIEKER_BUS), still[0][0] if still else 0), 10)
        t.check("Resume brings new rows again", bool(resumed))

        addresses = set(a for _, a in browser.evaluate(rows_js(RIEKER_BUS)))
        t.check("the Rieker bus's rows name more than one address",
                {"223", "224"} <= addresses, addresses)
        browser.fill(panel(RIEKER_BUS) + " .traffic-filter", "223")
        shown = browser.evaluate(rows_js(RIEKER_BUS))
        hidden = browser.evaluate("document.querySelectorAll(%s).length" %
                                  json.dumps(panel(RIEKER_BUS) + " tbody tr[data-n][hidden]"))
        t.check("the address filter shows address 223's rows only, the others hidden",
                shown and all(a == "223" for _, a in shown) and hidden > 0, (shown[:5], hidden))
        time.sleep(1)
        shown = browser.evaluate(rows_js(RIEKER_BUS))
        t.check("rows that come later are filtered too",
                shown and all(a == "223" for _, a in shown), shown[:5])
        verdicts = ("[...document.querySelectorAll(%s)].map(c => [c.textContent, "
                    "c.classList.contains('bad')])" % json.dumps(panel(RTU_BUS) + " td.verdict"))
        browser.run("document.querySelector(%s).open = true" % json.dumps(panel(RTU_BUS)))
        browser.wait_for("%s.length > 4" % verdicts, 10)
        admin_api.request("POST", "/api/buses/%s/raw" % RTU_BUS,
                          {"address": 1, "function": 3, "data": "FF 00 00 01"})
        red = browser.wait_for("%s.filter(([, bad]) => bad)" % verdicts, 10)
        seen = browser.evaluate(verdicts) or []
        t.check("a refused request's reply is red, with its refusal; requests and good replies "
                "are not", red and all(text == "CRC ok \u00B7 nak 0x02" for text, _ in red) and
                any(text == "request" and not bad for text, bad in seen) and
                any(text == "CRC ok" and not bad for text, bad in seen), (red, seen[:6]))
        link = browser.evaluate("document.querySelector(%s).getAttribute('href')" %
                                json.dumps(panel(RIEKER_BUS) + " .traffic-download"))
        t.check("the download link is the bus's capture.pcapng",
                link == "/api/buses/%s/capture.pcapng" % RIEKER_BUS, link)

        # A phone: the bytes hide until a row is tapped.
        browser.send("Emulation.setDeviceMetricsOverride",
                     {"width": 390, "height": 844, "deviceScaleFactor": 1, "mobile": True})
        time.sleep(0.5)
        bytes_cell = panel(RIEKER_BUS) + " tbody tr[data-n]:not([hidden]) td.bytes"
        display = "getComputedStyle(document.querySelector(%s)).display" % json.dumps(bytes_cell)
        before = browser.evaluate(display)
        browser.click(panel(RIEKER_BUS) + " .traffic-pause")   # the row tapped stays put
        browser.click(panel(RIEKER_BUS) + " tbody tr[data-n]:not([hidden]) td.function")
        after = browser.evaluate(display)
        wide = browser.evaluate("document.documentElement.scrollWidth")
        t.check("on a phone: no bytes until a tap, then the row's bytes; nothing wider than the "
                "screen", before == "none" and after == "block" and wide <= 390,
                (before, after, wide))
        blocked = browser.csp_violations()
        t.check("the Content-Security-Policy blocked nothing", blocked == [], blocked)

        browser.send("Emulation.setDeviceMetricsOverride",
                     {"width": 1280, "height": 900, "deviceScaleFactor": 1, "mobile": False})
        browser.click("#logout")
        t.check("logged out, no frame stays on the page",
                browser.wait_for("document.querySelectorAll('details.traffic tbody tr').length === 0"
                                 " && !document.querySelector('details.traffic[open]')", 5))
        t.check("the operator logs in", log_in(browser, operator) == "operator")
        browser.click('.tab[data-tab="buses"]')
        time.sleep(0.5)
        t.check("an operator has no Traffic view",
                browser.evaluate("[...document.querySelectorAll('details.traffic')]"
                                 ".every(d => d.hidden && d.offsetParent === null)"))
    finally:
        browser.close()


def scenario(t):
    tiltgate, _ = arguments()
    demo, http_port, out_path = start_demo(t, tiltgate, "demo")
    accounts = processes.wait_until(
        lambda: (lambda a: a if len(a) == 3 else None)(printed_accounts(out_path)), 30) or {}
    t.check("the demo prints its accounts", set(accounts) == {"admin", "operator", "viewer"},
            processes.tail(out_path))

    def serving():
        try:
            return Client(http_port).request("GET", "/healthz")[0] == 200
        except OSError:
            return False
    t.check("the console answers", processes.wait_until(serving, 20), processes.tail(out_path))
    admin, operator = Client(http_port), Client(http_port)
    t.check("the admin and the operator log in",
            admin.login("admin", accounts.get("admin"))[0] == 200 and
            operator.login("operator", accounts.get("operator"))[0] == 200)
    # The RTU bus polls its one device several times a second: enough frames within 3 s.
    # after=0: a look that starts no view, so the trail's count of views below stays exact.
    processes.wait_until(lambda: len(frames_of(admin, RTU_BUS, 0)[1].get("frames", [])) >= 20, 10)
    api_checks(t, admin, operator, t.dir)
    browser_checks(t, "http://127.0.0.1:%d/" % http_port, "admin:" + accounts.get("admin", ""),
                   "operator:" + accounts.get("operator", ""), admin)
    demo.terminate()
    demo.wait(timeout=20)


if __name__ == "__main__":
    sys.exit(Checks("console-traffic").run(scenario))
