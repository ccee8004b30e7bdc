"""A warm standby pair on one simulated line (docs/operations.md, "Warm standby"), as the
warm_standby*_test.py and standby_feeds_test.py scripts run it: `tiltgate sim rieker
--second-master` with its counters in a file, and two `tiltgate run` gateways, each in a folder
of its own (its own state_dir, as two boxes have), the same sensors, one on each master port,
with [redundancy] pointing at each other.

Under a sanitizer (scripts/sanitize sets ASAN_OPTIONS or TSAN_OPTIONS) the gateways run many
times slower: the same behaviour is checked with more time to take over and more slack on what
the tests' own timing measures. The figures of docs/operations.md are the plain build's."""
import json
import os
import subprocess
import time
import urllib.request

import spb_path  # noqa: F401  (spb_e2e on the import path)
from network_plant import Gateway, bus
from spb_e2e import processes
from spb_e2e.processes import wait_until

SANITIZED = "ASAN_OPTIONS" in os.environ or "TSAN_OPTIONS" in os.environ
POLL_MS = 100
TAKEOVER_MS = 4000 if SANITIZED else 1000
SLACK_S = 1.5 if SANITIZED else 0.3  # the tests' own polling of /api/status, and load
ADDRESSES = (223, 224)


class TwoMasterSim:
    """`tiltgate sim rieker` with two master ports on one line and its counters in a file."""

    def __init__(self, tiltgate, scratch_dir):
        self.link = os.path.join(scratch_dir, "primary-tty")
        self.second = os.path.join(scratch_dir, "standby-tty")
        self.stats_path = os.path.join(scratch_dir, "line-stats.json")
        self.err_path = os.path.join(scratch_dir, "sim.err")
        sensors = ",".join("h6:%d" % a for a in ADDRESSES)
        argv = [tiltgate, "sim", "rieker", "--sensors", sensors, "--link", self.link,
                "--second-master", self.second, "--stats", self.stats_path]
        self.process = processes.start(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                       stderr=open(self.err_path, "w"), text=True, bufsize=1)
        self.process.stdout.readline()
        if not wait_until(lambda: os.path.exists(self.second) and os.path.exists(self.stats_path), 5):
            raise RuntimeError("the simulator did not start:\n" + processes.tail(self.err_path))

    def command(self, line):
        self.process.stdin.write(line + "\n")
        self.process.stdin.flush()
        return self.process.stdout.readline().strip()

    def stats(self):
        for _ in range(20):
            try:
                with open(self.stats_path) as f:
                    return json.load(f)
            except (OSError, ValueError):
                time.sleep(0.05)
        return {}

    def sent(self, index):
        masters = self.stats().get("masters", [])
        return masters[index].get("bytes_sent") if len(masters) > index else None


def status(gateway):
    try:
        return json.loads(urllib.request.urlopen(
            "http://127.0.0.1:%d/api/status" % gateway.http_port, timeout=3).read())
    except OSError:
        return {}


def role(gateway):
    return status(gateway).get("role")


def age_of(plc, unit):
    """Input register 7, age_ms: how old the reading served is; None when the read fails."""
    r = plc.client.read_input_registers(7, 1, slave=unit)
    return None if r.isError() else r.registers[0]


def add_redundancy(gateway, my_role, peer_port):
    """Writes enabled, and [redundancy] as `my_role` with the peer at 127.0.0.1:`peer_port`."""
    with open(gateway.config_path) as f:
        text = f.read()
    with open(gateway.config_path, "w") as f:
        f.write(text.replace("[server]\n", "[server]\nwrites = true\n", 1))
    with open(gateway.config_path, "a") as f:
        f.write('\n[redundancy]\nrole = "%s"\npeer = "127.0.0.1:%d"\ntakeover_ms = %d\n'
                % (my_role, peer_port, TAKEOVER_MS))


def make_pair(t, tiltgate, sim, peer_ports=None):
    """(primary, standby), not started, their logs shown on a failure; each file ends in its
    [redundancy] table. `peer_ports`: each one's peer port (default: each other's Modbus
    port)."""
    sensors = [("s%d" % a, "h6", a, i + 1, {"poll_ms": POLL_MS}) for i, a in enumerate(ADDRESSES)]
    gateways = []
    for name, link in (("primary", sim.link), ("standby", sim.second)):
        os.makedirs(os.path.join(t.dir, name))
        gateway = Gateway(tiltgate, os.path.join(t.dir, name),
                          [bus("line1", link, "rieker", sensors)], name=name)
        t.logs.append((name, gateway.log_path))
        gateways.append(gateway)
    primary, standby = gateways
    ports = peer_ports or (standby.modbus_port, primary.modbus_port)
    add_redundancy(primary, "primary", ports[0])
    add_redundancy(standby, "standby", ports[1])
    return primary, standby
