#!/usr/bin/env python3
"""A warm standby pair cut off from each other on the network, both alive on the line (issue
56, docs/operations.md "Warm standby"): each one's peer address is a black hole (a port that
takes connections and never answers, as a firewall that drops the pair's traffic looks to the
question). The standby hears the primary's requests, so it never transmits, however long the
cut lasts; once the primary is killed it takes the line, having no answer from the peer. No
collision on the line.

Usage: /usr/bin/python3 warm_standby_partition_test.py path/to/tiltgate
"""
import os
import signal
import socket
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import ModbusReader  # noqa: E402
from spb_e2e import processes  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from standby_pair import TAKEOVER_MS, TwoMasterSim, make_pair, role  # noqa: E402


class BlackHole:
    """A loopback port that takes connections into its backlog and never answers."""

    def __init__(self):
        self.port = processes.free_port()
        self.socket = socket.socket()
        self.socket.bind(("127.0.0.1", self.port))
        self.socket.listen(64)


def scenario(t):
    tiltgate, _ = arguments()
    sim = TwoMasterSim(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    holes = BlackHole(), BlackHole()
    primary, standby = make_pair(t, tiltgate, sim, peer_ports=(holes[0].port, holes[1].port))
    primary.start()
    t.check("the primary takes the line", wait_until(lambda: role(primary) == "active", 10),
            primary.log())
    standby.start()
    plc = ModbusReader(standby.modbus_port)
    t.check("the standby, cut off from its peer, serves warm from what it hears",
            wait_until(lambda: (lambda g: g is not None and g.online)(plc.read(1)), 10),
            standby.log())
    time.sleep(5 * TAKEOVER_MS / 1000)
    t.check("over five takeover times it stayed the standby",
            role(standby) == "standby", standby.log())
    t.check("and sent nothing on the line", sim.sent(1) == 0, sim.stats())
    os.kill(primary.process.pid, signal.SIGKILL)
    t.check("with the primary killed, it takes the line though its peer never answers",
            wait_until(lambda: role(standby) == "active", TAKEOVER_MS / 1000 + 4), standby.log())
    t.check("its requests go out", wait_until(lambda: (sim.sent(1) or 0) > 0, 3), sim.stats())
    t.check("no collision on the line", sim.stats().get("collisions") == 0, sim.stats())
    plc.close()
    t.check("the gateway stops cleanly", standby.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("warm-standby-partition").run(scenario))
