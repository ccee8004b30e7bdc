#!/usr/bin/env python3
"""The web console's scan and raw frames as a new user meets them (issue 54, defects 1 and 4;
docs/web-console.md, "The API"): build/tiltgate run on two simulated Rieker buses, line1 with
devices at 5, 6 and 7 (boom at 5 and jib at 6 configured, unit ids 1 and 2) and line2 with mast
(unit id 3) at 101.

1. A scan of line1 marks 5 and 6 "already configured" (configured_as, no table to add) and
   proposes for 7 the lowest unit id no configured unit has (4, not mast's 3); the served
   configuration with that table added passes `tiltgate check`.
4. A raw frame the sensor answers with NAK 2 (Set Zero To Value on the Y axis of an H4360,
   after unlocking it) shows the NAK in the endpoint's reply, and its audit record says
   "nak 0x02", not an exit code.

Usage: /usr/bin/python3 console_bus_actions_test.py path/to/tiltgate
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import Client, start_gateway  # noqa: E402
from spb_e2e import processes  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Simulator  # noqa: E402

ADMIN, PASSWORD = "bob", "admin-pass-22"

CONFIG = """[server]
listen = "127.0.0.1"
port = %(modbus)d
control_socket = ""
state_dir = "%(dir)s/state"

[http]
listen = "127.0.0.1"
port = %(http)d
users_file = "%(users)s"

[[bus]]
name = "line1"
port = "%(line1)s"
protocol = "rieker"

[[bus]]
name = "line2"
port = "%(line2)s"
protocol = "rieker"

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 5
unit_id = 1

[[sensor]]
name = "jib"
bus = "line1"
model = "h6"
address = 6
unit_id = 2

[[sensor]]
name = "mast"
bus = "line2"
model = "h4360"
address = 101
unit_id = 3
"""

# Change Lock to level 1 with the factory password (12345678 = 00 BC 61 4E), then Set Zero To
# Value on axis 2 (Y), 0.0: an H4360 has no Y axis, so it answers NAK 2.
UNLOCK = {"address": 101, "function": 10, "data": "01 00 BC 61 4E"}
ZERO_Y = {"address": 101, "function": 25, "data": "02 00 00 00 00"}


def scan(console, bus, low, high):
    status, body = console.request("POST", "/api/buses/%s/scan" % bus, {"from": low, "to": high})
    if status != 202:
        return None, (status, body)
    processes.wait_until(
        lambda: not console.request("GET", "/api/buses/%s/scan" % bus)[1].get("running", True), 60)
    return console.request("GET", "/api/buses/%s/scan" % bus)[1], None


def scenario(t):
    tiltgate, _ = arguments()
    users = os.path.join(t.dir, "users")
    done = subprocess.run([tiltgate, "user", "add", ADMIN, "--role", "admin", "--users-file",
                           users], input=PASSWORD + "\n", text=True, capture_output=True,
                          timeout=30)
    t.check("the admin's account is made", done.returncode == 0, done.stderr)
    line1 = Simulator(tiltgate, t.dir, {"boom": {"model": "h6", "address": 5},
                                        "jib": {"model": "h6", "address": 6},
                                        "new": {"model": "h6", "address": 7}}, name="line1")
    line2 = Simulator(tiltgate, t.dir, {"mast": {"model": "h4360", "address": 101}},
                      name="line2")
    t.logs.append(("line1 simulator", line1.err_path))
    t.logs.append(("line2 simulator", line2.err_path))
    http_port = processes.free_port()
    served = CONFIG % {"modbus": processes.free_port(), "http": http_port, "dir": t.dir,
                       "users": users, "line1": line1.link, "line2": line2.link}
    config = os.path.join(t.dir, "gateway.toml")
    with open(config, "w") as f:
        f.write(served)
    log_path = os.path.join(t.dir, "gateway.log")
    t.logs.append(("gateway", log_path))
    gateway = start_gateway(tiltgate, config, log_path, http_port)
    console = Client(http_port)
    status, _ = console.login(ADMIN, PASSWORD)
    t.check("the admin logs in", status == 200, status)

    # 1. What a scan proposes.
    state, error = scan(console, "line1", 4, 8)
    found = {s["address"]: s for s in (state or {}).get("found", [])}
    t.check("the scan of line1 finds 5, 6 and 7", sorted(found) == [5, 6, 7], error or state)
    t.check("5 and 6 are marked already configured as boom and jib, with no table to add",
            [(found.get(a, {}).get("configured_as"), found.get(a, {}).get("config"),
              found.get(a, {}).get("proposed_unit_id")) for a in (5, 6)] ==
            [("boom", "", None), ("jib", "", None)], state)
    new = found.get(7, {})
    t.check("7 is new, with the lowest unit id no configured sensor has: 4 (mast has 3)",
            new.get("configured_as") is None and new.get("proposed_unit_id") == 4 and
            "unit_id = 4 " in new.get("config", ""), new)
    added = os.path.join(t.dir, "added.toml")
    with open(added, "w") as f:
        f.write(served + "\n" + new.get("config", ""))
    checked = subprocess.run([tiltgate, "check", "--config", added], capture_output=True,
                             text=True, timeout=60)
    t.check("the configuration with 7's table added passes `tiltgate check`",
            checked.returncode == 0, (checked.stdout, checked.stderr))

    # 4. A raw frame answered with NAK 2.
    status, body = console.request("POST", "/api/buses/line2/raw", UNLOCK)
    t.check("the H4360 is unlocked by a raw Change Lock: ACK",
            status == 200 and "ACK" in body.get("decoded", ""), (status, body))
    status, body = console.request("POST", "/api/buses/line2/raw", ZERO_Y)
    t.check("a raw Set Zero To Value on its Y axis: the reply shows NAK 2 and its meaning",
            status == 200 and body.get("received") and
            "NAK 2 (function not valid for this sensor or mode)" in body.get("decoded", "") and
            "exit code" not in str(body), (status, body))
    status, body = console.request("GET", "/api/audit?door=console")
    records = [r for r in (body.get("records", []) if isinstance(body, dict) else [])
               if r["setting"].startswith("function 25")]
    t.check("its audit record says nak 0x02, not an exit code",
            [(r["who"], r["new"], r["result"]) for r in records] ==
            [(ADMIN, "0200000000", "nak 0x02")], body)
    gateway.terminate()
    gateway.wait(timeout=20)


if __name__ == "__main__":
    sys.exit(Checks("console-bus-actions").run(scenario))
