#!/usr/bin/env python3
"""Fail-back of a warm standby pair (issue 56, docs/operations.md "Warm standby"), with
`failback = true` on both: the primary is killed, the standby takes the line; the primary
starts again, listens first (it hears the standby polling, so it sends nothing), and the
standby, finding the primary back and listening, gives the line back; the primary takes it.
No collision on the line at any point.

Usage: /usr/bin/python3 warm_standby_failback_test.py path/to/tiltgate
"""
import os
import signal
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import ModbusReader  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from standby_pair import TAKEOVER_MS, TwoMasterSim, make_pair, role, status  # noqa: E402


def with_failback(gateway):
    with open(gateway.config_path, "a") as f:
        f.write("failback = true\n")  # the file ends in [redundancy]


def scenario(t):
    tiltgate, _ = arguments()
    sim = TwoMasterSim(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    primary, standby = make_pair(t, tiltgate, sim)
    with_failback(primary)
    with_failback(standby)
    primary.start()
    t.check("the primary takes the line", wait_until(lambda: role(primary) == "active", 10),
            primary.log())
    standby.start()
    t.check("the standby listens", wait_until(lambda: role(standby) == "standby", 5))
    time.sleep(1.0)
    t.check("and stays the standby while the primary runs, failback or not",
            role(standby) == "standby" and sim.sent(1) == 0, (status(standby), sim.stats()))

    os.kill(primary.process.pid, signal.SIGKILL)
    primary.process.wait()
    t.check("with the primary killed, the standby takes the line",
            wait_until(lambda: role(standby) == "active", TAKEOVER_MS / 1000 + 4), standby.log())
    primary.start()
    t.check("the primary, started again, listens first",
            role(primary) == "standby", status(primary))
    t.check("the standby gives the line back, and the primary takes it",
            wait_until(lambda: role(primary) == "active" and role(standby) == "standby",
                       2 * TAKEOVER_MS / 1000 + 6),
            (status(primary), status(standby)))
    plc = ModbusReader(primary.modbus_port)
    t.check("the PLC reads fresh readings through the primary",
            wait_until(lambda: (lambda g: g is not None and g.online)(plc.read(1)), 3))
    sent = sim.sent(1)
    time.sleep(1.0)
    t.check("the standby sends nothing after it gave the line back", sim.sent(1) == sent,
            sim.stats())
    t.check("no collision on the line", sim.stats().get("collisions") == 0, sim.stats())
    plc.close()
    t.check("the gateways stop cleanly", primary.stop() == 0 and standby.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("warm-standby-failback").run(scenario))
