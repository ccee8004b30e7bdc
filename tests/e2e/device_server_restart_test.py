#!/usr/bin/env python3
"""A serial device server killed and started again mid-run (issue 43): two Rieker lines behind
Debian's ser2net, one raw (`tcp://`), one RFC 2217 (`rfc2217://`, ser2net's connector at 9600,
the sensors at 62500). Killed (kill -9, as a server losing power): every sensor of both lines goes
offline (status register bit 0, the HTTP status) while the gateway keeps serving Modbus;
started again on the same ports: the gateway reconnects with its back-off and every sensor is
back online with its angles. On the RFC 2217 line that also proves the rate is set again at each
connection: ser2net starts every new connection at its configured 9600.

Usage: /usr/bin/python3 device_server_restart_test.py path/to/tiltgate
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import Gateway, ModbusReader, Simulator, bus, close_to  # noqa: E402
from ser2net_server import Ser2net  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

WAIT = 15
SENSORS = "h6:223,h4360:101"
ANGLES = {223: (12.5, -3.25), 101: (-45.0, None)}
BUS_KEYS = {"timeout_ms": 50, "retries": 1, "reopen_min_ms": 100, "reopen_max_ms": 400}


def scenario(t):
    tiltgate, _ = arguments()
    if not shutil.which("ser2net"):
        t.check("ser2net is installed (Debian package ser2net; run scripts/setup)", False)
        return
    lines = {"raw": (125000, 125000), "rfc2217": (62500, 9600)}  # mode: (sensors' rate, ser2net's)
    servers, buses, units = {}, [], {}
    unit = 0
    for mode, (rate, server_rate) in lines.items():
        sim = Simulator(tiltgate, t.dir, "rieker", SENSORS, baud=rate, name="sim-" + mode)
        t.logs.append(("simulator " + mode, sim.err_path))
        for address, (x, y) in ANGLES.items():
            sim.command("angle %d %s" % (address, x if y is None else "%s %s" % (x, y)))
        servers[mode] = Ser2net(t.dir, sim.link, server_rate, mode, name="ser2net-" + mode)
        servers[mode].start()
        t.logs.append(("ser2net " + mode, servers[mode].log_path))
        sensors = []
        for address, model in ((223, "h6"), (101, "h4360")):
            unit += 1
            name = "%s_%d" % (mode, address)
            sensors.append((name, model, address, unit, {"poll_ms": 100}))
            units[unit] = (name, ANGLES[address])
        buses.append(bus("line-" + mode, servers[mode].url, "rieker", sensors, baud=rate,
                         **BUS_KEYS))
    gateway = Gateway(tiltgate, t.dir, buses)
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    modbus = ModbusReader(gateway.modbus_port)

    def reading_right(unit_id):
        got = modbus.read(unit_id)
        x, y = units[unit_id][1]
        return got and got[2] and close_to(got[0], x) and (y is None or close_to(got[1], y))

    def offline(unit_id):
        return modbus.online(unit_id) is False and modbus.angles_exception(unit_id) == 0x0B

    every = lambda test: all(test(u) for u in units)
    t.check("every sensor of both lines online with its angles",
            wait_until(lambda: every(reading_right), WAIT),
            ([modbus.read(u) for u in units], gateway.log()))

    for server in servers.values():
        server.kill()
    t.check("ser2net killed: every sensor of both lines offline (status bit 0 clear, its angles "
            "read as exception 0x0B)", wait_until(lambda: every(offline), WAIT),
            ([(modbus.online(u), modbus.angles_exception(u)) for u in units], gateway.log()))
    t.check("ser2net killed: the HTTP status says offline for every sensor",
            all(gateway.sensor(name).get("online") is False for name, _ in units.values()),
            [gateway.sensor(name) for name, _ in units.values()])

    for server in servers.values():
        server.start()
    t.check("ser2net started again: every sensor of both lines back online with its angles",
            wait_until(lambda: every(reading_right), WAIT),
            ([modbus.read(u) for u in units], gateway.log()))
    t.check("ser2net started again: the HTTP status says online for every sensor",
            all(gateway.sensor(name).get("online") is True for name, _ in units.values()),
            [gateway.sensor(name) for name, _ in units.values()])
    modbus.close()
    t.check("the gateway stops cleanly", gateway.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("device-server-restart").run(scenario))
