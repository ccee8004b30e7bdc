#!/usr/bin/env python3
"""A line behind a device server far away (issue 43, "the network in the timing"): two Rieker H6
with different angles on one bus, served by Debian's ser2net (raw), with a relay between the
gateway and ser2net that delays each direction by D ms (tests/e2e/support/delay_relay.py; the
kernel has no netem), D = 30 and 60: a round trip of 60 and 120 ms, longer than the bus's
`timeout_ms = 50`. The relay's own socket acknowledges at once, so the kernel's measure of the
TCP round trip (which the gateway adds to every reply wait) sees none of the delay: here it is
each sensor's adapted reply wait (up to `max_timeout_ms`, 500) that must take it in, as it does
for a device server whose serial side is slow (device_server_netem_test.py delays the packets
themselves, where the kernel has netem). A fresh gateway for each D:
- both sensors come online and stay online, with new readings arriving, and their reply wait
  (input register 36) adapted past the round trip;
- every reading of either unit is that sensor's own angles: nothing is taken for the other
  sensor's reply.
Then the link goes down (every connection reset, each new one too): both offline; up again: both
back online with their own angles.

Usage: /usr/bin/python3 device_server_delay_test.py path/to/tiltgate
"""
import os
import shutil
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from delay_relay import DelayRelay  # noqa: E402
from network_plant import Gateway, ModbusReader, Simulator, bus, close_to  # noqa: E402
from ser2net_server import Ser2net  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

WAIT = 20
WINDOW_S = 1.5
RATE = 125000
SENSORS = {1: (223, (12.5, -3.25)), 2: (224, (-30.0, 40.0))}  # unit: (address, (x, y))


def own(reading, unit):
    x, y = SENSORS[unit][1]
    return reading is not None and close_to(reading.x, x) and close_to(reading.y, y)


def run_at(t, tiltgate, ser2net, delay_ms, last):
    relay = DelayRelay(ser2net.port, delay_ms)
    relay.start()
    sensors = [("s%d" % unit, "h6", address, unit, {"poll_ms": 100})
               for unit, (address, _) in SENSORS.items()]
    # The bus's own keys are the defaults a line on a local tty has (timeout_ms 50).
    gateway = Gateway(tiltgate, t.dir, [bus("far", "tcp://127.0.0.1:%d" % relay.port, "rieker",
                                            sensors, baud=RATE, reopen_min_ms=100,
                                            reopen_max_ms=400)],
                      name="gateway-%dms" % delay_ms)
    t.logs.append(("gateway at %d ms" % delay_ms, gateway.log_path))
    gateway.start()
    modbus = ModbusReader(gateway.modbus_port)
    both_online = lambda: all((r := modbus.read(u)) and r.online and own(r, u) for u in SENSORS)
    t.check("D = %d ms (round trip %d ms > timeout_ms 50): both sensors online with their angles"
            % (delay_ms, 2 * delay_ms), wait_until(both_online, WAIT),
            ([modbus.read(u) for u in SENSORS], gateway.log()))

    samples = {u: [] for u in SENSORS}
    end = time.monotonic() + WINDOW_S
    while time.monotonic() < end:
        for u in SENSORS:
            samples[u].append(modbus.read(u))
        time.sleep(0.02)
    for u, (address, angles) in SENSORS.items():
        seen = samples[u]
        t.check("D = %d ms: every one of %d reads of unit %d is online" % (delay_ms, len(seen), u),
                all(r is not None and r.online for r in seen),
                [r for r in seen if r is None or not r.online][:5])
        t.check("D = %d ms: every read of unit %d is sensor %d's own angles %s (never the other's)"
                % (delay_ms, u, address, angles), all(own(r, u) for r in seen),
                [r for r in seen if not own(r, u)][:5])
        t.check("D = %d ms: unit %d's readings are new ones (sample_seq moves)" % (delay_ms, u),
                seen and seen[-1] is not None and seen[0] is not None and seen[-1].seq != seen[0].seq,
                (seen[0], seen[-1]))
        t.check("D = %d ms: unit %d's reply wait (input register 36) adapted past the %d ms "
                "round trip" % (delay_ms, u, 2 * delay_ms),
                (modbus.reply_timeout_ms(u) or 0) > 2 * delay_ms, modbus.reply_timeout_ms(u))

    if last:
        relay.link_down()
        offline = lambda: all(modbus.online(u) is False for u in SENSORS)
        t.check("D = %d ms, the link down: both sensors offline" % delay_ms,
                wait_until(offline, WAIT), ([modbus.online(u) for u in SENSORS], gateway.log()))
        relay.link_up()
        t.check("D = %d ms, the link up again: both sensors back online with their own angles"
                % delay_ms, wait_until(both_online, WAIT),
                ([modbus.read(u) for u in SENSORS], gateway.log()))
    modbus.close()
    t.check("D = %d ms: the gateway stops cleanly" % delay_ms, gateway.stop() == 0)
    relay.stop()


def scenario(t):
    tiltgate, _ = arguments()
    if not shutil.which("ser2net"):
        t.check("ser2net is installed (Debian package ser2net; run scripts/setup)", False)
        return
    sim = Simulator(tiltgate, t.dir, "rieker", ",".join("h6:%d" % a for a, _ in SENSORS.values()),
                    baud=RATE)
    t.logs.append(("simulator", sim.err_path))
    for address, (x, y) in SENSORS.values():
        t.check("the simulator sets %d's angles" % address,
                sim.command("angle %d %s %s" % (address, x, y)) == "ok")
    ser2net = Ser2net(t.dir, sim.link, RATE, "raw")
    ser2net.start()
    t.logs.append(("ser2net", ser2net.log_path))
    run_at(t, tiltgate, ser2net, 30, last=False)
    run_at(t, tiltgate, ser2net, 60, last=True)


if __name__ == "__main__":
    sys.exit(Checks("device-server-delay").run(scenario))
