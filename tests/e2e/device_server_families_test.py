#!/usr/bin/env python3
"""Lines behind a real serial device server (issue 43): Debian's ser2net serves each simulator's
pseudo-terminal, and `tiltgate run` reaches it with `port = "tcp://..."` (raw: ser2net's own
rate on the line) or `port = "rfc2217://..."` (the gateway sets the rate over RFC 2217). Every
family's protocol over both: Rieker, Spectron Modbus-ASCII and Modbus RTU (the example device
profile), read with pymodbus: the angles right, the status online.

Each simulator answers only at its bus's rate (`tiltgate sim ... --baud N`). In rfc2217 mode
ser2net's connector is configured at 9600, another rate, so a sensor answers only if the gateway
really set the far port's rate; and the reverse: in raw mode with ser2net at the wrong rate the
sensor stays offline (the gateway cannot set anything over raw TCP).

Usage: /usr/bin/python3 device_server_families_test.py path/to/tiltgate
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import RTU_PROFILE, Gateway, ModbusReader, Simulator, bus, close_to  # noqa: E402
from ser2net_server import Ser2net  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

WRONG_RATE = 9600  # what ser2net's connector starts at in rfc2217 mode; no simulator's rate
POLL = {"poll_ms": 100}

# name, sim family, sim --protocol, sensor spec, bus protocol, model, address, rate,
# the console command setting its angles (or None: the preset's), expected (x, y)
LINES = [
    ("rieker", "rieker", None, "h6:223", "rieker", "h6", 223, 62500,
     "angle 223 12.5 -3.25", (12.5, -3.25)),
    ("spectron", "spectron", "modbus", "dyna:7", "spectron-modbus", "dyna", 7, 38400,
     "counts 7 1250", (12.5, None)),
    ("rtu", "modbus-rtu", None, "modbus-rtu:5", "modbus-rtu", "modbus-rtu", 5, 38400,
     None, (1.0, -1.0)),  # the RTU simulator's preset angles (modbus_rtu/simulator/inclinometer_preset.h)
]


def scenario(t):
    tiltgate, _ = arguments()
    if not shutil.which("ser2net"):
        t.check("ser2net is installed (Debian package ser2net; run scripts/setup)", False)
        return
    buses, expected, servers = [], {}, {}
    unit = 0
    for name, family, protocol, spec, bus_protocol, model, address, rate, command, angles in LINES:
        for mode in ("raw", "rfc2217"):
            unit += 1
            sim = Simulator(tiltgate, t.dir, family, spec, baud=rate, protocol=protocol,
                            name="%s-%s" % (name, mode))
            t.logs.append(("%s %s simulator" % (name, mode), sim.err_path))
            if command:
                t.check("%s %s: the simulator takes %r" % (name, mode, command),
                        sim.command(command) == "ok")
            # raw: ser2net keeps the line at the simulator's rate; rfc2217: it starts at
            # another, and only the gateway's SET-BAUDRATE brings it to the simulator's.
            server = Ser2net(t.dir, sim.link, rate if mode == "raw" else WRONG_RATE, mode,
                             name="ser2net-%s-%s" % (name, mode))
            server.start()
            t.logs.append(("%s %s ser2net" % (name, mode), server.log_path))
            servers[unit] = server
            more = dict(POLL, device=RTU_PROFILE) if family == "modbus-rtu" else dict(POLL)
            buses.append(bus("%s-%s" % (name, mode), server.url, bus_protocol,
                             [("%s_%s" % (name, mode), model, address, unit, more)], baud=rate))
            expected[unit] = ("%s over %s" % (name, mode), angles)

    # The reverse: raw TCP with ser2net at a rate the sensor does not speak.
    unit += 1
    wrong_unit = unit
    sim = Simulator(tiltgate, t.dir, "rieker", "h6:223", baud=125000, name="rieker-wrong-rate")
    server = Ser2net(t.dir, sim.link, WRONG_RATE, "raw", name="ser2net-wrong-rate")
    server.start()
    buses.append(bus("rieker-wrong-rate", server.url, "rieker",
                     [("rieker_wrong_rate", "h6", 223, wrong_unit, dict(POLL))], baud=125000))

    gateway = Gateway(tiltgate, t.dir, buses)
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    modbus = ModbusReader(gateway.modbus_port)

    def right(unit_id):
        got = modbus.read(unit_id)
        x, y = expected[unit_id][1]
        return got and got[2] and close_to(got[0], x) and (y is None or close_to(got[1], y))

    for unit_id, (title, (x, y)) in expected.items():
        t.check("%s: pymodbus reads unit %d online with x = %s%s" %
                (title, unit_id, x, "" if y is None else ", y = %s" % y),
                wait_until(lambda: right(unit_id), 15), (modbus.read(unit_id), gateway.log()))
        name = title.replace(" over ", "_")
        t.check("%s: the HTTP status says online" % title,
                gateway.sensor(name).get("online") is True, gateway.sensor(name))

    # The wrong-rate line: given as long as the others took, and more polls, it never answers.
    t.check("raw TCP with ser2net at the wrong rate: polled and failing",
            wait_until(lambda: gateway.sensor("rieker_wrong_rate").get("polls_failed", 0) >= 3, 15),
            gateway.sensor("rieker_wrong_rate"))
    t.check("raw TCP with ser2net at the wrong rate: the sensor stays offline (status bit 0 clear)",
            modbus.online(wrong_unit) is False, modbus.online(wrong_unit))
    t.check("raw TCP with ser2net at the wrong rate: its angles read as exception 0x0B",
            modbus.angles_exception(wrong_unit) == 0x0B, modbus.angles_exception(wrong_unit))
    t.check("raw TCP with ser2net at the wrong rate: the HTTP status says offline",
            gateway.sensor("rieker_wrong_rate").get("online") is False,
            gateway.sensor("rieker_wrong_rate"))
    modbus.close()
    t.check("the gateway stops cleanly", gateway.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("device-server-families").run(scenario))
