#!/usr/bin/env python3
"""Temperature beside the angle (issue 57, item 6), from outside: two Dyna modules under `tiltgate
sim spectron` (Modbus-ASCII), a Modbus RTU inclinometer under `tiltgate sim modbus-rtu` and an H6
under `tiltgate sim rieker`, each on its own pty, read through build/tiltgate by pymodbus and
HTTP. The Dyna's counts become degC by the assumed 0.1 degC per count, or by the sensor's own
temperature keys; the RTU profile's `temperature` value is in degC; the H6 has none (NaN at
input 50, null in the API). A thermal cycle driven through the simulator's console shows in the
long record's temperature_min/max; `tiltgate check` refuses a conversion that divides by 0, and
the temperature keys on a sensor that is no Dyna, each at its line.

Usage: /usr/bin/python3 temperature_test.py path/to/tiltgate
"""
import csv
import io
import json
import os
import struct
import subprocess
import sys
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import RTU_PROFILE, Gateway, ModbusReader, Simulator, bus, close_to  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

POLL = {"poll_ms": 100}
DYNA_UNIT, OWN_UNIT, RTU_UNIT, H6_UNIT = 1, 2, 3, 4


def temperature_register(reader, unit):
    """Input register 50 as float32 (big-endian words), or None when the read fails."""
    r = reader.client.read_input_registers(50, 2, slave=unit)
    if r.isError():
        return None
    return struct.unpack(">f", struct.pack(">HH", *r.registers))[0]


def api_temperature(gateway, name):
    return gateway.sensor(name).get("temperature", "absent")


def history_rows(gateway, sensor, since_ms):
    text = urllib.request.urlopen("http://127.0.0.1:%d/api/sensors/%s/history.csv?from=%d"
                                  % (gateway.http_port, sensor, since_ms), timeout=10).read()
    return list(csv.DictReader(io.StringIO(text.decode())))


def check_refuses(t, tiltgate, config_text, path, key, why):
    with open(path, "w") as f:
        f.write(config_text)
    checked = subprocess.run([tiltgate, "check", "--config", path], capture_output=True,
                             text=True, timeout=30)
    t.check("tiltgate check refuses %s, naming the key at its line" % why,
            checked.returncode != 0 and key in checked.stderr + checked.stdout and
            "%s:" % os.path.basename(path) in checked.stderr + checked.stdout,
            (checked.returncode, checked.stdout, checked.stderr))


def scenario(t):
    tiltgate, _ = arguments()
    # Raw temperatures 250 and 260 (sensor_spec.h: 250 + 10 * position).
    dyna = Simulator(tiltgate, t.dir, "spectron", "dyna:7,dyna:8", baud=38400,
                     protocol="modbus", name="dyna")
    rtu = Simulator(tiltgate, t.dir, "modbus-rtu", "modbus-rtu:5", baud=38400, name="rtu")
    h6 = Simulator(tiltgate, t.dir, "rieker", "h6:223", name="h6")
    for sim, name in ((dyna, "Dyna"), (rtu, "RTU"), (h6, "H6")):
        t.logs.append(("%s simulator" % name, sim.err_path))
    own = dict(POLL, temperature_counts_per_degree=20, temperature_zero_counts=50)
    gateway = Gateway(tiltgate, t.dir, [
        bus("dyna-line", dyna.link, "spectron-modbus",
            [("dyna", "dyna", 7, DYNA_UNIT, dict(POLL)), ("own", "dyna", 8, OWN_UNIT, own)],
            baud=38400),
        bus("rtu-line", rtu.link, "modbus-rtu",
            [("rtu", "modbus-rtu", 5, RTU_UNIT, dict(POLL, device=RTU_PROFILE))], baud=38400),
        bus("h6-line", h6.link, "rieker", [("h6", "h6", 223, H6_UNIT, dict(POLL))]),
    ])
    with open(gateway.config_path) as f:
        config_text = f.read()
    with open(gateway.config_path, "a") as f:
        f.write("\n[record]\ninterval_s = 1\nkeep_days = 1\n")
    t.logs.append(("gateway", gateway.log_path))

    checked = subprocess.run([tiltgate, "check", "--config", gateway.config_path],
                             capture_output=True, text=True, timeout=30)
    t.check("tiltgate check accepts the temperature keys on a Dyna", checked.returncode == 0,
            checked.stdout + checked.stderr)
    bad = os.path.join(t.dir, "bad.toml")
    check_refuses(t, tiltgate, config_text.replace("temperature_counts_per_degree = 20",
                                                   "temperature_counts_per_degree = 0"),
                  bad, "temperature_counts_per_degree", "a temperature conversion dividing by 0")
    check_refuses(t, tiltgate, config_text + "temperature_zero_counts = 5\n", bad,
                  "temperature_zero_counts", "a Dyna's temperature key on an H6")

    gateway.start()
    reader = ModbusReader(gateway.modbus_port)
    t.check("Dyna: 250 counts read 25.0 degC (0.1 degC per count) in /api/sensors",
            wait_until(lambda: close_to(api_temperature(gateway, "dyna"), 25.0), 15),
            gateway.sensor("dyna"))
    t.check("Dyna: input register 50 reads 25.0 as float32",
            close_to(temperature_register(reader, DYNA_UNIT), 25.0),
            temperature_register(reader, DYNA_UNIT))
    t.check("Dyna with its own keys: (260 - 50) / 20 = 10.5 degC",
            wait_until(lambda: close_to(api_temperature(gateway, "own"), 10.5), 15),
            gateway.sensor("own"))
    t.check("RTU device: the profile's temperature (int16 tenths, scale 0.1) reads 21.5 degC",
            wait_until(lambda: close_to(api_temperature(gateway, "rtu"), 21.5), 15) and
            close_to(temperature_register(reader, RTU_UNIT), 21.5),
            (gateway.sensor("rtu"), temperature_register(reader, RTU_UNIT)))
    t.check("H6 online, with no temperature: null in the API",
            wait_until(lambda: gateway.sensor("h6").get("online") is True, 15) and
            api_temperature(gateway, "h6") is None, gateway.sensor("h6"))
    h6_register = temperature_register(reader, H6_UNIT)
    t.check("H6: input register 50 reads NaN", h6_register is not None and h6_register != h6_register,
            h6_register)

    def recent(name):
        return json.loads(urllib.request.urlopen("http://127.0.0.1:%d/api/sensors/%s/history"
                                                 % (gateway.http_port, name), timeout=10).read())
    t.check("the status page's recent samples carry the Dyna's temperature",
            wait_until(lambda: any(close_to(s.get("temperature"), 25.0) for s in recent("dyna")),
                       10), recent("dyna")[-3:])
    t.check("and none for the H6", recent("h6") and
            all("temperature" not in s for s in recent("h6")), recent("h6")[-3:])

    # A thermal cycle: the module's raw temperature from 5.0 to 35.0 degC and back, a step a
    # fifth of a second, while the long record keeps one row a second.
    since = int(time.time() * 1000)
    # The extremes are held a second, so a slow (sanitized) gateway polls them too.
    for raw in list(range(50, 351, 25)) + list(range(325, 49, -25)):
        t.check("the simulator takes temperature 7 %d" % raw,
                dyna.command("temperature 7 %d" % raw) == "ok")
        time.sleep(1.0 if raw in (50, 350) else 0.2)
    t.check("the API follows the module: 5.0 degC at the end of the cycle",
            wait_until(lambda: close_to(api_temperature(gateway, "dyna"), 5.0), 10),
            gateway.sensor("dyna"))

    def cycle_recorded():
        rows = [r for r in history_rows(gateway, "dyna", since) if r["temperature_max"]]
        highs = [float(r["temperature_max"]) for r in rows]
        lows = [float(r["temperature_min"]) for r in rows]
        return rows and max(highs) > 34.0 and min(lows) < 6.0 and all(
            float(r["temperature_min"]) <= float(r["temperature_mean"]) <= float(r["temperature_max"])
            for r in rows)
    t.check("the long record holds the cycle: temperature_max up to 35, temperature_min down to "
            "5, min <= mean <= max in every row", wait_until(cycle_recorded, 10),
            history_rows(gateway, "dyna", since)[-6:])
    h6_rows = history_rows(gateway, "h6", since)
    t.check("the H6's rows have empty temperature columns",
            h6_rows and all(r["temperature_mean"] == "" for r in h6_rows), h6_rows[:3])
    reader.close()
    t.check("the gateway stops cleanly", gateway.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("temperature").run(scenario))
