#!/usr/bin/env python3
"""Counters a technician can trust at a glance (issue 54, item 4; docs/web-console.md,
"Counters"): build/tiltgate on two simulated Rieker sensors and a third configured at an address
nobody answers, read with Python's http.client. Each sensor and bus shows its failures since
start beside those of the last 10 minutes (a bus's are its sensors'); an admin resets a
sensor's, or a bus's and its sensors', counters, which the status API, /metrics and the audit
trail show; an operator's reset is refused (403) and recorded.

Usage: /usr/bin/python3 console_counters_test.py path/to/tiltgate
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import (PASSWORDS, Client, add_users, by_name, start_gateway,  # noqa: E402
                              write_config)
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Simulator  # noqa: E402
from spb_e2e import processes  # noqa: E402

GHOST = """
[[sensor]]
name = "ghost"
bus = "line1"
model = "h6"
address = 50
unit_id = 3
"""
CAUSES = ("polls_failed", "timeout", "checksum", "io_error", "late_reply")


def scenario(t):
    tiltgate, _ = arguments()
    users_file = os.path.join(t.dir, "users")
    add_users(tiltgate, users_file)
    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    modbus_port, http_port = processes.free_port(), processes.free_port()
    config = os.path.join(t.dir, "gateway.toml")
    write_config(config, modbus_port, http_port, sim, t.dir, users_file)
    with open(config, "a") as f:
        f.write(GHOST)
    log_path = os.path.join(t.dir, "gateway.log")
    t.logs.append(("gateway", log_path))
    start_gateway(tiltgate, config, log_path, http_port)
    bob, alice = Client(http_port), Client(http_port)
    t.check("the admin and an operator log in",
            bob.login("bob")[0] == 200 and alice.login("alice")[0] == 200)

    def sensors():
        return bob.request("GET", "/api/sensors")[1]

    def buses():
        return bob.request("GET", "/api/buses")[1]

    # The ghost fails every poll; the 10-minute counts come once two samples are kept (1 s).
    failing = processes.wait_until(
        lambda: (lambda g: g if g and g["polls_failed"] >= 3 and g["failures_10min"] else None)(
            by_name(sensors(), "ghost")), 20)
    t.check("a sensor that does not answer counts failures, since start and in the last 10 min",
            failing and failing["failures"]["timeout"] >= 3 and
            failing["failures_10min"]["timeout"] >= 1 and
            set(failing["failures_10min"]) == set(CAUSES), failing)
    boom = by_name(sensors(), "boom")
    t.check("a healthy sensor has none in the last 10 minutes",
            boom and boom["failures_10min"] is not None and
            all(boom["failures_10min"][c] == 0 for c in CAUSES), boom)
    line1 = by_name(buses(), "line1")
    t.check("a bus shows its sensors' failures since start and in the last 10 minutes",
            line1 and line1["failures"]["timeout"] >= failing["failures"]["timeout"] and
            line1["failures_10min"] is not None and line1["failures_10min"]["timeout"] >= 1,
            line1)

    # Line health by cause (docs/diagnostics.md): attempt by attempt, and the bus's hint.
    ghost = by_name(sensors(), "ghost")
    t.check("the ghost's exchanges: requests with no reply at all, nothing taken",
            ghost["exchanges"]["requests"] >= 3 and ghost["exchanges"]["replies"] == 0 and
            ghost["exchanges"]["no_reply"] == ghost["exchanges"]["requests"] and
            ghost["exchanges"]["bytes_out"] > 0, ghost["exchanges"])
    boom = by_name(sensors(), "boom")
    t.check("a healthy sensor's: every request answered, bytes both ways",
            boom["exchanges"]["requests"] > 0 and boom["exchanges"]["no_reply"] == 0 and
            boom["exchanges"]["replies"] >= boom["exchanges"]["requests"] - 1 and
            boom["exchanges"]["bytes_in"] > 0, boom["exchanges"])
    line1 = by_name(buses(), "line1")
    t.check("the bus: its sensors' exchanges summed, the bytes its line carried, and a hint "
            "naming the one device that does not answer",
            line1["exchanges"]["no_reply"] >= ghost["exchanges"]["no_reply"] and
            line1["bytes_out"] >= line1["exchanges"]["bytes_out"] > 0 and
            line1["stray_bytes"] == 0 and
            (line1["hint"] or "").startswith("ghost does not answer while its neighbours do") and
            "address (50)" in line1["hint"], line1)

    status, reply = alice.request("POST", "/api/sensors/ghost/counters/reset", {})
    t.check("an operator's reset: 403 saying why", status == 403 and
            reply.get("error") == "resetting counters is for the admin role", (status, reply))
    status, reply = bob.request("POST", "/api/sensors/nosuch/counters/reset", {})
    t.check("a reset of a sensor not served: 404", status == 404, (status, reply))
    status, reply = bob.request("GET", "/api/sensors/ghost/counters/reset")
    t.check("a reset is a POST: GET is 405", status == 405, (status, reply))

    before = by_name(sensors(), "ghost")
    status, reply = bob.request("POST", "/api/sensors/ghost/counters/reset", {})
    t.check("the admin resets the ghost's counters: 200", status == 200 and
            reply == {"sensor": "ghost", "counters": "reset"}, (status, reply))
    after = by_name(sensors(), "ghost")
    t.check("its counts since start begin again from zero (at most a poll or two since)",
            after["polls_failed"] < before["polls_failed"] and after["polls_failed"] <= 2 and
            after["failures"]["timeout"] < before["failures"]["timeout"], (before, after))
    metrics = bob.request("GET", "/metrics")[1]
    line = 'tiltgate_sensor_failures_total{sensor="ghost",bus="line1",unit="3",reason="timeout"} '
    counted = [l for l in metrics.splitlines() if l.startswith(line)]
    t.check("/metrics counts from the reset too (a counter reset, as at a restart)",
            counted and int(float(counted[0].split()[-1])) < before["failures"]["timeout"],
            (counted, before["failures"]["timeout"]))
    boom_after = by_name(sensors(), "boom")
    t.check("another sensor's counters are left alone",
            boom_after["polls_ok"] >= boom["polls_ok"], (boom, boom_after))

    polls_before = by_name(buses(), "line1")["polls"]
    status, reply = bob.request("POST", "/api/buses/line1/counters/reset", {})
    t.check("the admin resets bus line1's counters: 200", status == 200 and
            reply == {"bus": "line1", "counters": "reset"}, (status, reply))
    line1 = by_name(buses(), "line1")
    boom_reset = by_name(sensors(), "boom")
    t.check("the bus's counts and its sensors' begin again",
            line1["polls"] < polls_before and boom_reset["polls_ok"] < boom_after["polls_ok"],
            (polls_before, line1, boom_after, boom_reset))

    page = subprocess.run(
        [sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support",
                                      "chromium_page.py"),
         "counters", "http://127.0.0.1:%d/" % http_port, "bob:" + PASSWORDS["bob"], "ghost"],
        capture_output=True, text=True, timeout=120)
    t.check("in Chromium: the failing card red for the last 10 min, each bus's counters, a "
            "confirmed reset", page.returncode == 0, page.stdout + page.stderr)

    status, body = bob.request("GET", "/api/audit?door=console&setting=counters")
    records = body.get("records", []) if status == 200 else []
    resets = [(r["who"], r["sensor"], r["result"]) for r in records]
    t.check("each reset and the refused one is an audit record, door console, with who",
            ("bob", "ghost", "ok") in resets and resets.count(("bob", "line1", "ok")) == 2 and
            ("alice", "ghost", "refused: resetting counters is for the admin role") in resets,
            resets)


if __name__ == "__main__":
    sys.exit(Checks("console-counters").run(scenario))
