#!/usr/bin/env python3
"""Try the console in one command (issue 54, item 3; docs/web-console.md, "Try it"):
`tiltgate demo` serves the web console with three accounts made for this run, admin, operator
and viewer, and prints their passwords beside its mbpoll lines. Each logs in with the printed
password and has its role; the admin scans the demo's Rieker bus, adds the sensor fitted there
but not configured with the sensor form, and applies it (the demo serves a file of its own);
the API needs a login; a second run prints other passwords;
`--no-accounts` serves the open status API as before. Read with Python's http.client.

Usage: /usr/bin/python3 demo_console_test.py path/to/tiltgate
"""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import Client  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e import processes  # noqa: E402

ACCOUNT = re.compile(r"^  (admin|operator|viewer) +(\S+)   \(")


def start_demo(t, tiltgate, name, *extra):
    """A demo with its HTTP side on a port of its own; (process, http_port, out_path)."""
    http_port = processes.free_port()
    out_path = os.path.join(t.dir, name + ".out")
    t.logs.append((name, out_path))
    env = dict(os.environ, TMPDIR=t.dir)
    demo = processes.start(
        [tiltgate, "demo", "--port", str(processes.free_port()), "--http-port", str(http_port)] +
        list(extra), stdout=open(out_path, "w"), stderr=subprocess.STDOUT, env=env, cwd=t.dir)
    return demo, http_port, out_path


def printed_accounts(out_path):
    with open(out_path) as f:
        return {m.group(1): m.group(2) for m in map(ACCOUNT.match, f.read().splitlines()) if m}


def scan_and_add(t, admin):
    """The walkthrough's scan and add: the demo's file holds five sensors; boom-tip, fitted at
    225 on demo-bus, is not among them until the admin adds it."""
    status, body = admin.request("POST", "/api/buses/demo-bus/scan", {"from": 220, "to": 230})
    t.check("the admin scans demo-bus from 220 to 230: the demo serves a file, so it may",
            status == 202, (status, body))
    done = processes.wait_until(
        lambda: (lambda s: s if not s["running"] and s["progress"] == 1 else None)(
            admin.request("GET", "/api/buses/demo-bus/scan")[1]), 60)
    found = {f["address"]: f for f in (done or {}).get("found", [])}
    t.check("the scan finds boom-left and boom-right configured, and boom-tip at 225 to add "
            "with the free unit id 6",
            found.get(223, {}).get("configured_as") == "boom-left" and
            found.get(224, {}).get("configured_as") == "boom-right" and
            found.get(225, {}).get("proposed_unit_id") == 6, done)
    status, served = admin.request("GET", "/api/config")
    status_tables, proposal = admin.request("POST", "/api/config/tables",
                                            {"text": found.get(225, {}).get("config", "")})
    values = dict(proposal["sensors"][0]["values"]) if status_tables == 200 and \
        proposal.get("sensors") else {}
    values["name"] = "boom-tip"
    status, made = admin.request("POST", "/api/config/form", {
        "text": served.get("text", ""), "action": "add", "table": "sensor", "values": values})
    t.check("the Add a sensor form, filled from the scan, makes a valid text",
            status == 200 and made.get("ok"), (status, made, values))
    status, applied = admin.request("PUT", "/api/config", {"text": made.get("text") or ""})
    confirmed = processes.wait_until(
        lambda: admin.request("POST", "/api/config/confirm")[0] == 200, 20)
    serving = processes.wait_until(
        lambda: any(s["name"] == "boom-tip" and s.get("online")
                    for s in admin.request("GET", "/api/sensors")[1]), 20)
    t.check("applied and confirmed, the demo reloads its file and serves boom-tip",
            status == 200 and confirmed and serving, (status, applied))


def scenario(t):
    tiltgate, _ = arguments()
    demo, http_port, out_path = start_demo(t, tiltgate, "demo")
    accounts = processes.wait_until(
        lambda: (lambda a: a if len(a) == 3 else None)(printed_accounts(out_path)), 30)
    t.check("the demo prints three accounts, admin, operator and viewer, with passwords",
            accounts and set(accounts) == {"admin", "operator", "viewer"} and
            all(len(p) >= 10 for p in accounts.values()), processes.tail(out_path))
    with open(out_path) as f:
        out = f.read()
    t.check("beside the mbpoll lines, with the console's address",
            "mbpoll -m tcp" in out and "http://127.0.0.1:%d/" % http_port in out, out)
    accounts = accounts or {}

    def serving():
        try:
            return Client(http_port).request("GET", "/healthz")[0] == 200
        except OSError:
            return False
    t.check("the console answers", processes.wait_until(serving, 20), processes.tail(out_path))
    status, _ = Client(http_port).request("GET", "/api/sensors")
    t.check("the API needs a login", status == 401, status)
    for name in ("operator", "viewer", "admin"):  # the walkthrough's order
        password = accounts.get(name, "")
        client = Client(http_port)
        status, body = client.login(name, password)
        t.check("%s logs in with the printed password, as %s" % (name, name),
                status == 200 and body.get("role") == name, (status, body))
        if name == "viewer":
            status, body = client.request("POST", "/api/sensors/boom-left/settings",
                                          {"setting": "filter", "value": 3})
            t.check("the viewer may change nothing", status == 403, (status, body))
        if name == "operator":  # the walkthrough's step 2
            status, body = client.request("POST", "/api/sensors/boom-left/settings",
                                          {"setting": "command", "value": 1})
            t.check("the operator zeroes boom-left to its current angle: the sensor's ACK",
                    status == 200 and body.get("result") == "ack", (status, body))
        if name == "admin":  # steps 3 and 4
            status, body = client.request("GET", "/api/sensors")
            t.check("the admin reads the demo's sensors",
                    status == 200 and any(s["name"] == "boom-left" for s in body), (status, body))
            status, body = client.request("POST", "/api/buses/%s/counters/reset" % body[0]["bus"],
                                          {})
            t.check("the admin resets a bus's counters", status == 200, (status, body))
            scan_and_add(t, client)
            status, body = client.request("GET", "/api/audit?door=console")
            seen = [(r["who"], r["setting"], r["result"]) for r in body.get("records", [])]
            t.check("the audit lists the operator's zero, the admin's reset and apply",
                    ("operator", "command", "ack") in seen and
                    ("admin", "counters", "ok") in seen and
                    any(w == "admin" and s == "config" for w, s, _ in seen), seen)
    status, _ = Client(http_port).login("admin", "not-the-password")
    t.check("a wrong password is refused", status == 401, status)
    demo.terminate()
    t.check("Ctrl-C stops the demo", demo.wait(timeout=20) == 0)

    again, _, again_out = start_demo(t, tiltgate, "demo-again")
    second = processes.wait_until(
        lambda: (lambda a: a if len(a) == 3 else None)(printed_accounts(again_out)), 30)
    t.check("a second run makes other passwords",
            second and all(second[n] != accounts.get(n) for n in second), (accounts, second))
    again.terminate()
    again.wait(timeout=20)

    plain, plain_port, plain_out = start_demo(t, tiltgate, "demo-plain", "--no-accounts")
    def api_open():
        try:
            return Client(plain_port).request("GET", "/api/sensors")[0] == 200
        except OSError:
            return False
    opened = processes.wait_until(api_open, 30)
    t.check("--no-accounts: the status API is open, as before", opened,
            processes.tail(plain_out))
    t.check("--no-accounts prints no accounts", not printed_accounts(plain_out),
            processes.tail(plain_out))
    plain.terminate()
    plain.wait(timeout=20)


if __name__ == "__main__":
    sys.exit(Checks("demo-console").run(scenario))
