#!/usr/bin/env python3
"""The monitoring in the web console (issue 57, items 2, 5 and 7; docs/web-console.md, "What
the console shows", and docs/monitoring.md): build/tiltgate on two simulated Rieker sensors with a 1-second long record, read
with Python's http.client and in headless Chromium. Anyone logged in reads a sensor's baseline;
the admin sets it to the current reading or to angles, or back to the configuration's, each an
audit record and an event, and the relative angles follow; an operator's change is refused
(403) and recorded; a request that makes no sense gets 400 saying why. The long record answers
a graph's range merged into at most `points` rows, and refuses a bad `points`. In Chromium the
sensor's graph zooms from the recent minutes to the long record, and the header says the clock.

Usage: /usr/bin/python3 console_monitoring_test.py path/to/tiltgate
"""
import csv
import io
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import (PASSWORDS, Client, add_users, by_name, start_gateway,  # noqa: E402
                              write_config)
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Simulator  # noqa: E402
from spb_e2e import processes  # noqa: E402


def scenario(t):
    tiltgate, _ = arguments()
    users_file = os.path.join(t.dir, "users")
    add_users(tiltgate, users_file)
    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    t.check("the simulator takes boom's angles", sim.command("angle 223 2.0 -1.0") == "ok")
    modbus_port, http_port = processes.free_port(), processes.free_port()
    config = os.path.join(t.dir, "gateway.toml")
    write_config(config, modbus_port, http_port, sim, t.dir, users_file)
    with open(config, "a") as f:
        f.write("\n[record]\ninterval_s = 1\nkeep_days = 1\n")
    log_path = os.path.join(t.dir, "gateway.log")
    t.logs.append(("gateway", log_path))
    start_gateway(tiltgate, config, log_path, http_port)
    bob, alice, carol = Client(http_port), Client(http_port), Client(http_port)
    t.check("the admin, an operator and a viewer log in",
            bob.login("bob")[0] == 200 and alice.login("alice")[0] == 200 and
            carol.login("carol")[0] == 200)
    t.check("boom is read", processes.wait_until(
        lambda: (by_name(carol.request("GET", "/api/sensors")[1], "boom") or {}).get("x"), 15))

    status, shown = carol.request("GET", "/api/sensors/boom/baseline")
    t.check("a viewer reads the baseline: the configuration's 0, 0",
            status == 200 and shown == {"sensor": "boom", "x": 0.0, "y": 0.0, "stored": False},
            (status, shown))
    status, reply = alice.request("POST", "/api/sensors/boom/baseline", {"set": "current"})
    t.check("an operator's change: 403 saying why",
            status == 403 and reply.get("error") == "changing a baseline is for the admin role",
            (status, reply))
    status, reply = bob.request("POST", "/api/sensors/boom/baseline", {"set": "sideways"})
    t.check("a request that makes no sense: 400 saying what is wanted",
            status == 400 and "current, value, clear or show" in reply.get("error", ""),
            (status, reply))
    status, reply = bob.request("POST", "/api/sensors/boom/baseline",
                                {"set": "value", "x": 400})
    t.check("an angle past 180: 400", status == 400 and "180" in reply.get("error", ""),
            (status, reply))
    status, reply = bob.request("POST", "/api/sensors/nosuch/baseline", {"set": "current"})
    t.check("a sensor not served: 404", status == 404, (status, reply))
    status, reply = bob.request("PUT", "/api/sensors/boom/baseline", {"set": "current"})
    t.check("another method: 405", status == 405, (status, reply))

    status, reply = bob.request("POST", "/api/sensors/boom/baseline",
                                {"set": "value", "x": 1.5, "y": -0.5})
    t.check("the admin sets angles: 200 with the baseline, stored, by bob",
            status == 200 and reply.get("x") == 1.5 and reply.get("y") == -0.5 and
            reply.get("stored") is True and "bob" in reply.get("by", ""), (status, reply))
    boom = processes.wait_until(
        lambda: (lambda s: s if s and s.get("relative_x") is not None and
                 abs(s["relative_x"] - (s["x"] - 1.5)) < 0.01 else None)(
            by_name(bob.request("GET", "/api/sensors")[1], "boom")), 10)
    t.check("the relative angles follow: x - 1.5, y + 0.5",
            boom and abs(boom["relative_y"] - (boom["y"] + 0.5)) < 0.01, boom)
    status, reply = bob.request("POST", "/api/sensors/boom/baseline", {"set": "current"})
    t.check("the admin sets the current reading: 200, about (2, -1)",
            status == 200 and abs(reply.get("x", 0) - 2.0) < 0.05 and
            abs(reply.get("y", 0) + 1.0) < 0.05, (status, reply))
    status, reply = bob.request("POST", "/api/sensors/boom/baseline", {"set": "clear"})
    t.check("and back to the configuration's: stored false",
            status == 200 and reply.get("stored") is False and reply.get("x") == 0.0,
            (status, reply))

    status, body = bob.request("GET", "/api/audit?door=console&setting=baseline")
    records = body.get("records", []) if status == 200 else []
    results = [(r["who"], r["result"]) for r in records]
    t.check("each change and the refused one is an audit record, door console, with who",
            results.count(("bob", "ok")) == 3 and
            ("alice", "refused: changing a baseline is for the admin role") in results, records)
    status, events = bob.request("GET", "/api/events?kind=baseline")
    t.check("each change is an event", status == 200 and len(events) == 3, events)

    # The long record for a graph: a row a second, merged into at most `points`.
    time.sleep(4)
    now = int(time.time() * 1000)
    status, text = bob.request("GET", "/api/sensors/boom/history.csv?from=%d&to=%d&points=2"
                               % (now - 60000, now))
    rows = list(csv.DictReader(io.StringIO(text))) if status == 200 else []
    t.check("history.csv with points=2 over a minute: at most 2 rows, each merged from several",
            status == 200 and 1 <= len(rows) <= 2 and
            max(int(r["samples"]) for r in rows) > 10, (status, text[:400]))
    for bad in ("0", "x", "10001"):
        status, reply = bob.request("GET", "/api/sensors/boom/history.csv?from=%d&points=%s"
                                    % (now - 60000, bad))
        t.check("points=%s: 400 saying what is wanted" % bad,
                status == 400 and "points: expected a whole number 1..10000" in str(reply),
                (status, reply))

    page = subprocess.run(
        [sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support",
                                      "chromium_page.py"),
         "monitoring", "http://127.0.0.1:%d/" % http_port, "bob:" + PASSWORDS["bob"], "boom"],
        capture_output=True, text=True, timeout=120)
    t.check("in Chromium: the clock in the header, the baseline set from the sensor's panel, "
            "the graph zoomed to the long record", page.returncode == 0, page.stdout + page.stderr)


if __name__ == "__main__":
    sys.exit(Checks("console-monitoring").run(scenario))
