#!/usr/bin/env python3
"""The connection's round trip in every reply wait (issue 43, "the network in the timing"), on a
kernel without netem: Debian's ser2net runs in a network namespace reached through a delay line
for IP packets (tests/e2e/support/tun_delay_line.py: two TUN devices, every packet held 30 ms
each way), so the kernel's TCP round trip measure sees the 60 ms. The bus has `timeout_ms = 50`
and `max_timeout_ms = 50`: no sensor's own reply wait may adapt, so the two Rieker H6 come
online and stay online only if the gateway adds the connection's measured round trip to the
wait; their reply wait (input register 36) stays 50; every reading is each sensor's own.

Needs root and /dev/net/tun; exits 77 where they are missing.

Usage: /usr/bin/python3 device_server_round_trip_test.py path/to/tiltgate
"""
import os
import shutil
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import Gateway, ModbusReader, Simulator, bus, close_to  # noqa: E402
from ser2net_server import Ser2net  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from tun_delay_line import TunDelayLine  # noqa: E402

SKIP = 77
WAIT = 20
WINDOW_S = 1.5
RATE = 125000
ONE_WAY_MS = 30
SENSORS = {1: (223, (12.5, -3.25)), 2: (224, (-30.0, 40.0))}  # unit: (address, (x, y))


def own(reading, unit):
    x, y = SENSORS[unit][1]
    return reading is not None and close_to(reading.x, x) and close_to(reading.y, y)


def scenario(t, line):
    tiltgate, _ = arguments()
    if not shutil.which("ser2net"):
        t.check("ser2net is installed (Debian package ser2net; run scripts/setup)", False)
        return
    sim = Simulator(tiltgate, t.dir, "rieker", ",".join("h6:%d" % a for a, _ in SENSORS.values()),
                    baud=RATE)
    t.logs.append(("simulator", sim.err_path))
    for address, (x, y) in SENSORS.values():
        sim.command("angle %d %s %s" % (address, x, y))
    ser2net = Ser2net(t.dir, sim.link, RATE, "raw", host=line.far_address, netns=line.netns)
    ser2net.start()
    t.logs.append(("ser2net", ser2net.log_path))
    sensors = [("s%d" % unit, "h6", address, unit, {"poll_ms": 100})
               for unit, (address, _) in SENSORS.items()]
    gateway = Gateway(tiltgate, t.dir, [bus("far", ser2net.url, "rieker", sensors, baud=RATE,
                                            timeout_ms=50, max_timeout_ms=50)])
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    modbus = ModbusReader(gateway.modbus_port)
    both_online = lambda: all((r := modbus.read(u)) and r.online and own(r, u) for u in SENSORS)
    t.check("%d ms round trip, max_timeout_ms 50: both sensors online with their own angles"
            % (2 * ONE_WAY_MS), wait_until(both_online, WAIT),
            ([modbus.read(u) for u in SENSORS], gateway.log()))
    samples = {u: [] for u in SENSORS}
    end = time.monotonic() + WINDOW_S
    while time.monotonic() < end:
        for u in SENSORS:
            samples[u].append(modbus.read(u))
        time.sleep(0.02)
    for u, (address, _) in SENSORS.items():
        seen = samples[u]
        t.check("every one of %d reads of unit %d is online" % (len(seen), u),
                all(r is not None and r.online for r in seen),
                [r for r in seen if r is None or not r.online][:5])
        t.check("every read of unit %d is sensor %d's own angles" % (u, address),
                all(own(r, u) for r in seen), [r for r in seen if not own(r, u)][:5])
        t.check("unit %d's readings are new ones (sample_seq moves)" % u,
                seen[0] is not None and seen[-1] is not None and seen[-1].seq != seen[0].seq,
                (seen[0], seen[-1]))
        t.check("unit %d's own reply wait (register 36) stayed 50 ms: the round trip was added "
                "by the connection" % u, modbus.reply_timeout_ms(u) == 50,
                modbus.reply_timeout_ms(u))
    modbus.close()
    t.check("the gateway stops cleanly", gateway.stop() == 0)


def main():
    if os.geteuid() != 0:
        print("SKIP: needs root (a network namespace and TUN devices)")
        return SKIP
    if not shutil.which("ip"):
        print("FAIL: ip not found (Debian package iproute2). Run scripts/setup.")
        return 1
    line = TunDelayLine(ONE_WAY_MS)
    try:
        line.start()
    except OSError as e:
        print("SKIP: cannot make the delay line here (%s)" % e)
        return SKIP
    try:
        return Checks("device-server-round-trip").run(lambda t: scenario(t, line))
    finally:
        line.stop()


if __name__ == "__main__":
    sys.exit(main())
