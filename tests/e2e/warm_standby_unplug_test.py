#!/usr/bin/env python3
"""A warm standby pair when the primary's adapter is unplugged (issue 56, docs/operations.md
"Warm standby"): the primary's line closes, so after half of takeover_ms, the peer answering,
it stands down; the standby hears the silence, finds the peer listening, and takes the line.
Plugged back, the old primary listens, hears the standby polling, and stays the standby (no
fail-back by default). The standby sent nothing before; no collision on the line.

Usage: /usr/bin/python3 warm_standby_unplug_test.py path/to/tiltgate
"""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import ModbusReader  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from standby_pair import SLACK_S, TAKEOVER_MS, TwoMasterSim, make_pair, role, status  # noqa: E402


def scenario(t):
    tiltgate, _ = arguments()
    sim = TwoMasterSim(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    primary, standby = make_pair(t, tiltgate, sim)
    primary.start()
    t.check("the primary takes the line", wait_until(lambda: role(primary) == "active", 10),
            primary.log())
    standby.start()
    plc = ModbusReader(standby.modbus_port)
    t.check("the standby serves warm",
            wait_until(lambda: (lambda g: g is not None and g.online)(plc.read(1)), 10),
            standby.log())
    time.sleep(0.5)
    t.check("the standby sent nothing so far", sim.sent(1) == 0, sim.stats())

    t.check("the simulator unplugs the primary's adapter", sim.command("unplug 1") == "ok")
    unplugged_at = time.monotonic()
    t.check("the primary, its line closed and its peer answering, stands down",
            wait_until(lambda: role(primary) == "standby", TAKEOVER_MS / 1000 + 4),
            (status(primary), primary.log()))
    t.check("the standby takes the line",
            wait_until(lambda: role(standby) == "active", TAKEOVER_MS / 1000 + 4),
            (status(standby), standby.log()))
    took_s = time.monotonic() - unplugged_at
    t.check("within takeover_ms and a second of the unplug (%.2f s)" % took_s,
            took_s <= TAKEOVER_MS / 1000 + 0.7 + SLACK_S, took_s)
    t.check("the PLC reads fresh readings through it",
            wait_until(lambda: (lambda g: g is not None and g.online)(plc.read(2)), 3))

    t.check("the simulator plugs the primary's adapter back", sim.command("replug 1") == "ok")
    time.sleep(0.5)
    sent = sim.sent(0)
    time.sleep(2 * TAKEOVER_MS / 1000)
    t.check("the old primary listens and stays the standby",
            role(primary) == "standby", (status(primary), primary.log()))
    t.check("it sends nothing", sim.sent(0) == sent, sim.stats())
    t.check("it hears the line again: a request heard lately",
            (status(primary).get("redundancy") or {}).get("last_request_heard_ms") is not None
            and status(primary)["redundancy"]["last_request_heard_ms"] < TAKEOVER_MS,
            status(primary))
    t.check("no collision on the line", sim.stats().get("collisions") == 0, sim.stats())
    plc.close()
    t.check("the gateway stops cleanly", standby.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("warm-standby-unplug").run(scenario))
