#!/usr/bin/env python3
"""A device server across a real (emulated) network (issue 43): Debian's ser2net runs in a network
namespace the test makes, reached over a veth pair whose both ends delay every packet with the
kernel's netem qdisc (30 ms each way: a 60 ms round trip, more than the bus's timeout_ms = 50),
and later lose some. Two Rieker H6 with different angles on the one bus:
- with the delay, both sensors come online and stay online (the reply wait took the round trip
  in: `max_timeout_ms = 50` leaves the sensors' own waits no room to adapt), and every reading is
  each sensor's own;
- with loss added, still nothing is taken for the other sensor's reply, and both are online at
  the end.
Needs root (namespaces, links, qdiscs) and a kernel with netem (sch_netem): where netem is
missing (this development machine's kernel and CI's) it exits 77 with the reason, and
tests/e2e/device_server_delay_test.py covers the delay with a userspace relay instead.

Usage: /usr/bin/python3 device_server_netem_test.py path/to/tiltgate
"""
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import Gateway, ModbusReader, Simulator, bus, close_to  # noqa: E402
from ser2net_server import Ser2net  # noqa: E402
import run_netns_mount  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

SKIP = 77
WAIT = 20
WINDOW_S = 3.0
RATE = 125000
SENSORS = {1: (223, (12.5, -3.25)), 2: (224, (-30.0, 40.0))}  # unit: (address, (x, y))
TAG = "tgnetem%d" % (os.getpid() % 100000)
NETNS, HOST_LINK, NS_LINK = TAG, TAG + "h", TAG + "n"
SUBNET = "10.254.%d" % (os.getpid() % 250)
HOST_ADDRESS, NS_ADDRESS = SUBNET + ".1", SUBNET + ".2"


def sh(*argv):
    """Runs a command; (ok, its output)."""
    done = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return done.returncode == 0, done.stdout.strip()


def make_network():
    """The namespace and the veth pair between it and here; None, or why it cannot be made."""
    steps = [["ip", "netns", "add", NETNS],
             ["ip", "link", "add", HOST_LINK, "type", "veth", "peer", "name", NS_LINK],
             ["ip", "link", "set", NS_LINK, "netns", NETNS],
             ["ip", "addr", "add", HOST_ADDRESS + "/30", "dev", HOST_LINK],
             ["ip", "link", "set", HOST_LINK, "up"],
             ["ip", "-n", NETNS, "addr", "add", NS_ADDRESS + "/30", "dev", NS_LINK],
             ["ip", "-n", NETNS, "link", "set", NS_LINK, "up"],
             ["ip", "-n", NETNS, "link", "set", "lo", "up"]]
    for argv in steps:
        ok, out = sh(*argv)
        if not ok:
            return "%s: %s" % (" ".join(argv), out)
    return None


NETNS_MOUNTED_BEFORE = run_netns_mount.was_mounted()


def remove_network():
    sh("ip", "link", "del", HOST_LINK)  # takes its peer along
    sh("ip", "netns", "del", NETNS)
    run_netns_mount.release(NETNS_MOUNTED_BEFORE)


def netem(action, spec):
    """`tc qdisc add|change ... netem SPEC` on both ends; None, or the error."""
    for prefix, link in ((["tc"], HOST_LINK), (["ip", "netns", "exec", NETNS, "tc"], NS_LINK)):
        ok, out = sh(*prefix, "qdisc", action, "dev", link, "root", "netem", *spec.split())
        if not ok:
            return "%s: %s" % (" ".join(prefix + ["qdisc", action, "dev", link, "root", "netem",
                                                  spec]), out)
    return None


def own(reading, unit):
    x, y = SENSORS[unit][1]
    return reading is not None and close_to(reading.x, x) and close_to(reading.y, y)


def sample(modbus):
    samples = {u: [] for u in SENSORS}
    end = time.monotonic() + WINDOW_S
    while time.monotonic() < end:
        for u in SENSORS:
            samples[u].append(modbus.read(u))
        time.sleep(0.02)
    return samples


def scenario(t):
    tiltgate, _ = arguments()
    if not shutil.which("ser2net"):
        t.check("ser2net is installed (Debian package ser2net; run scripts/setup)", False)
        return
    sim = Simulator(tiltgate, t.dir, "rieker", ",".join("h6:%d" % a for a, _ in SENSORS.values()),
                    baud=RATE)
    t.logs.append(("simulator", sim.err_path))
    for address, (x, y) in SENSORS.values():
        sim.command("angle %d %s %s" % (address, x, y))
    ser2net = Ser2net(t.dir, sim.link, RATE, "raw", host=NS_ADDRESS, netns=NETNS)
    ser2net.start()
    t.logs.append(("ser2net", ser2net.log_path))
    sensors = [("s%d" % unit, "h6", address, unit, {"poll_ms": 100})
               for unit, (address, _) in SENSORS.items()]
    # max_timeout_ms = timeout_ms: no sensor's reply wait may adapt, so only the connection's
    # round trip, which the kernel measures here since netem delays the packets themselves and
    # the gateway adds to every reply wait, can take the 60 ms in.
    gateway = Gateway(tiltgate, t.dir, [bus("far", ser2net.url, "rieker", sensors, baud=RATE,
                                            timeout_ms=50, max_timeout_ms=50)])
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    modbus = ModbusReader(gateway.modbus_port)
    both_online = lambda: all((r := modbus.read(u)) and r.online and own(r, u) for u in SENSORS)
    t.check("60 ms round trip (netem): both sensors online with their own angles",
            wait_until(both_online, WAIT), ([modbus.read(u) for u in SENSORS], gateway.log()))
    samples = sample(modbus)
    for u, (address, angles) in SENSORS.items():
        t.check("60 ms round trip: every read of unit %d is online" % u,
                all(r is not None and r.online for r in samples[u]),
                [r for r in samples[u] if r is None or not r.online][:5])
        t.check("60 ms round trip: every read of unit %d is sensor %d's own angles" % (u, address),
                all(own(r, u) for r in samples[u]), [r for r in samples[u] if not own(r, u)][:5])

    error = netem("change", "delay 30ms loss 10%")
    t.check("netem adds 10 % loss on both ends", error is None, error)
    samples = sample(modbus)
    for u, (address, angles) in SENSORS.items():
        t.check("10 %% loss: no online read of unit %d is another sensor's angles" % u,
                all(own(r, u) for r in samples[u] if r is not None and r.online),
                [r for r in samples[u] if r is not None and r.online and not own(r, u)][:5])
    netem("change", "delay 30ms")
    t.check("the loss taken away: both sensors online with their own angles",
            wait_until(both_online, WAIT), ([modbus.read(u) for u in SENSORS], gateway.log()))
    modbus.close()
    t.check("the gateway stops cleanly", gateway.stop() == 0)


def main():
    if os.geteuid() != 0:
        print("SKIP: needs root (network namespaces, veth links and qdiscs)")
        return SKIP
    for command, package in (("ip", "iproute2"), ("tc", "iproute2")):
        if not shutil.which(command):
            print("FAIL: %s not found (Debian package %s). Run scripts/setup." % (command, package))
            return 1
    why = make_network()
    if why:
        remove_network()
        print("SKIP: cannot make a network namespace with a veth pair here (%s)" % why)
        return SKIP
    try:
        why = netem("add", "delay 30ms")
        if why:
            print("SKIP: the kernel has no netem qdisc (sch_netem), so no delay can be added "
                  "on a link (%s); device_server_delay_test.py covers the delay with a relay" % why)
            return SKIP
        return Checks("device-server-netem").run(scenario)
    finally:
        remove_network()


if __name__ == "__main__":
    sys.exit(main())
