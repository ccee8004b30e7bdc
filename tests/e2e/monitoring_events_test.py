#!/usr/bin/env python3
"""Monitoring at the edge (issue 57, items 1, 2, 3 and 8): a simulated structure on
`tiltgate sim rieker` (an H6 on a mast, lever 10 m), read by `tiltgate run` with alarms at two
levels, for_ms, a baseline and a displacement, and checked from outside: noise at the warning
level that for_ms is set against sets no alarm; a step sets the warning, then the danger, each
no sooner than for_ms after the reading that passed; the events in order with their UTC times
in GET /api/events; the alarm bits, latches and acknowledgement over Modbus (pymodbus); the
displacement against the formula; `tiltgate baseline --current`, audited, kept across a
SIGKILL, as are the events.

Usage: /usr/bin/python3 monitoring_events_test.py path/to/tiltgate
"""
import json
import math
import os
import random
import struct
import subprocess
import sys
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Gateway, Simulator  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

MAST = {"mast": {"model": "h6", "address": 223, "unit_id": 1}}
# Under a sanitizer (scripts/sanitize sets ASAN_OPTIONS or TSAN_OPTIONS) every poll and tick is
# slower: the timing bounds get more slack, the behaviour is checked the same.
SANITIZED = "ASAN_OPTIONS" in os.environ or "TSAN_OPTIONS" in os.environ
SLACK_MS = 4000 if SANITIZED else 1000
LEVER_M = 10.0
FOR_MS = 600
WARNING, DANGER = 2.0, 4.0


def write_config(gateway, sim, state_dir, control_socket):
    lines = ["[server]", 'listen = "127.0.0.1"', "port = %d" % gateway.modbus_port,
             "writes = true", 'control_socket = "%s"' % control_socket,
             'state_dir = "%s"' % state_dir, "",
             "[http]", 'listen = "127.0.0.1"', "port = %d" % gateway.http_port, "",
             "[[bus]]", 'name = "line1"', 'port = "%s"' % sim.link, 'protocol = "rieker"', "",
             "[[sensor]]", 'name = "mast"', 'bus = "line1"', 'model = "h6"', "address = 223",
             "unit_id = 1", "poll_ms = 50", "lever_m = %g" % LEVER_M,
             "[sensor.alarms]", "x_high = %g" % WARNING, "hysteresis_deg = 0.2",
             "for_ms = %d" % FOR_MS, "[sensor.alarms.danger]", "x_high = %g" % DANGER]
    with open(gateway.config_path, "w") as f:
        f.write("\n".join(lines) + "\n")


def get_json(gateway, path):
    url = "http://127.0.0.1:%d%s" % (gateway.http_port, path)
    return json.loads(urllib.request.urlopen(url, timeout=5).read())


def events(gateway, query=""):
    return get_json(gateway, "/api/events" + query)


def alarm_events(gateway):
    return [e for e in events(gateway, "?kind=alarm&limit=1000")]


class Plc:
    def __init__(self, port):
        from pymodbus.client import ModbusTcpClient
        self.client = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
        if not self.client.connect():
            raise RuntimeError("pymodbus could not connect to port %d" % port)

    def floats(self, address, count):
        r = self.client.read_input_registers(address, 2 * count, slave=1)
        if r.isError():
            return None
        w = r.registers
        return [struct.unpack(">f", struct.pack(">HH", w[2 * i], w[2 * i + 1]))[0]
                for i in range(count)]

    def word(self, address):
        r = self.client.read_input_registers(address, 1, slave=1)
        return None if r.isError() else r.registers[0]

    def bits(self, address, count):
        r = self.client.read_discrete_inputs(address, count, slave=1)
        return None if r.isError() else list(r.bits[:count])


def hold(sim, x, seconds, noise=0.0, step=0.05):
    """The mast at x degrees for `seconds`, a new angle every `step`; with `noise`, each one
    off by a random 10..100 % of it, above and below in turn: a reading that keeps crossing
    its threshold, as a noisy one at the warning level does."""
    end = time.monotonic() + seconds
    sign = 1
    while time.monotonic() < end:
        value = x + (sign * random.uniform(0.1, 1.0) * noise if noise else 0.0)
        sign = -sign
        sim.command("angle 223 %.4f 0.0" % value)
        time.sleep(step)


def baseline_command(tiltgate, config, *args):
    return subprocess.run([tiltgate, "baseline", "--config", config, "--sensor", "mast"] +
                          list(args), capture_output=True, text=True, timeout=20)


def shown_x(text):
    """The X of `tiltgate baseline`'s line ("mast: baseline x 2 y 0 deg, ..."); NaN if none."""
    words = text.split()
    try:
        return float(words[words.index("x") + 1])
    except (ValueError, IndexError):
        return float("nan")


def scenario(t):
    tiltgate, _ = arguments()
    random.seed(57)
    sim = Simulator(tiltgate, t.dir, sensors=MAST)
    state_dir = os.path.join(t.dir, "state")
    control_socket = os.path.join(t.dir, "control.sock")
    gateway = Gateway(tiltgate, t.dir, sim, None)
    t.logs.append(("gateway", gateway.log_path))
    write_config(gateway, sim, state_dir, control_socket)
    sim.command("angle 223 0.0 0.0")
    gateway.start()
    plc = Plc(gateway.modbus_port)
    t.check("the sensor comes online and that is an event",
            wait_until(lambda: any(e["kind"] == "online" for e in events(gateway)), 10),
            events(gateway))

    # Noise of up to 0.15 degrees around the warning level for 4 s: past it at every other
    # reading, never for 600 ms in a row, so no alarm sets (without for_ms it would set and
    # clear every 100 ms: tests/unit/line_scheduling/alarm_tracker_test.cpp).
    hold(sim, WARNING, 4.0, noise=0.15)
    t.check("noise around the warning level sets no alarm (for_ms %d)" % FOR_MS,
            alarm_events(gateway) == [], alarm_events(gateway))

    # A step to 3 degrees: the warning sets, for_ms after the first reading past it.
    stepped = time.time()
    hold(sim, 3.0, 1.5)
    found = wait_until(lambda: len(alarm_events(gateway)) >= 1, 5 + SLACK_MS / 1000)
    warning = alarm_events(gateway)
    t.check("a step past the warning level sets x_high at the warning level",
            found and warning[-1]["alarm"] == "x_high" and warning[-1]["level"] == "warning" and
            warning[-1]["state"] == "set" and warning[-1]["threshold"] == WARNING and
            abs(warning[-1]["value"] - 3.0) < 1e-3, warning)
    if found:
        delay_ms = warning[-1]["unix_ms"] - stepped * 1000
        t.check("it set no sooner than for_ms after the step, within a second of it",
                FOR_MS - 60 <= delay_ms <= FOR_MS + SLACK_MS, delay_ms)
        t.check("its time is UTC ISO 8601 and agrees with unix_ms",
                warning[-1]["time"].endswith("Z") and
                warning[-1]["time"][:19] == time.strftime(
                    "%Y-%m-%dT%H:%M:%S", time.gmtime(warning[-1]["unix_ms"] / 1000)),
                warning[-1])
    t.check("Modbus: discrete input 1 (x high) is set, input 10 (danger) is not",
            plc.bits(1, 1) == [True] and plc.bits(10, 1) == [False], plc.bits(0, 13))

    hold(sim, 5.0, 1.5)
    wait_until(lambda: any(e["level"] == "danger" for e in alarm_events(gateway)), 5)
    t.check("a step past the danger level sets the danger x_high too",
            [(e["level"], e["state"]) for e in reversed(alarm_events(gateway))] ==
            [("warning", "set"), ("danger", "set")], alarm_events(gateway))
    t.check("Modbus: register 48 (danger) and 49 (latched) have bit 0, discrete 10 and 11 set",
            plc.word(48) == 1 and plc.word(49) == 1 and plc.bits(10, 2) == [True, True],
            (plc.word(48), plc.word(49), plc.bits(0, 13)))
    # The displacement at 10 m from the baseline 0: 1000 x 10 x sin 5 degrees.
    expected = 1000.0 * LEVER_M * math.sin(math.radians(5.0))
    d = plc.floats(42, 3)
    t.check("the displacement is 1000 x lever_m x (sin x - sin x0) mm (%.2f)" % expected,
            d is not None and abs(d[0] - expected) < 0.05 and abs(d[2] - expected) < 0.05, d)

    hold(sim, 0.0, 1.5)
    wait_until(lambda: len(alarm_events(gateway)) >= 4, 5)
    seen = [(e["level"], e["state"]) for e in reversed(alarm_events(gateway))]
    t.check("back to 0: both clear, and the events come in order",
            sorted(seen[2:]) == [("danger", "clear"), ("warning", "clear")], seen)
    times = [e["unix_ms"] for e in reversed(alarm_events(gateway))]
    seqs = [e["seq"] for e in events(gateway)]
    t.check("newest first: seq falls, and the alarms' times never go back",
            seqs == sorted(seqs, reverse=True) and times == sorted(times), (seqs, times))
    t.check("the alarm cleared but stays latched until acknowledged: register 49, input 11",
            plc.word(27) == 0 and plc.word(49) == 1 and plc.bits(11, 1) == [True],
            (plc.word(27), plc.word(49)))
    w = plc.client.write_coil(0, True, slave=1)
    t.check("a PLC acknowledges with coil 0: the latch goes, as the alarm is clear",
            not w.isError() and plc.word(49) == 0 and plc.bits(11, 1) == [False],
            (w, plc.word(49)))
    w = plc.client.write_coil(1, True, slave=1)
    t.check("a coil that is not the acknowledgement is refused (0x02)",
            w.isError() and getattr(w, "exception_code", None) == 2, w)

    # The baseline: the current reading (2 degrees) taken through the control socket.
    hold(sim, 2.0, 0.5)
    done = baseline_command(tiltgate, gateway.config_path, "--current")
    t.check("tiltgate baseline --current takes the reading as the baseline",
            done.returncode == 0 and abs(shown_x(done.stdout) - 2.0) < 1e-3,
            (done.stdout, done.stderr))
    rel = plc.floats(38, 1)
    t.check("relative_x (register 38) is now 0", rel is not None and abs(rel[0]) < 1e-3, rel)
    base = [e for e in events(gateway, "?kind=baseline")]
    t.check("the baseline is an event with the new and previous values and who set it",
            len(base) == 1 and abs(base[0]["value"]["x"] - 2.0) < 1e-3 and
            base[0]["value"]["y"] == 0 and base[0]["previous"] == {"x": 0, "y": 0} and
            base[0]["by"] != "",
            base)
    audit = subprocess.run([tiltgate, "audit", "--state-dir", state_dir, "--json"],
                           capture_output=True, text=True, timeout=20)
    t.check("the audit trail records the baseline and the acknowledgement",
            '"baseline"' in audit.stdout and '"acknowledge_alarms"' in audit.stdout, audit.stdout)
    bad = baseline_command(tiltgate, gateway.config_path, "--x", "500")
    t.check("a baseline out of range is refused with a clear error (exit 2)",
            bad.returncode == 2 and "-180..180" in bad.stderr, (bad.returncode, bad.stderr))

    # SIGKILL: the events and the baseline are on disk.
    before = events(gateway, "?limit=1000")
    gateway.kill()
    gateway.start()
    after = events(gateway, "?limit=1000")
    t.check("after a SIGKILL every event is still there, in order",
            after[-len(before):] == before if len(after) >= len(before) else False,
            (len(before), len(after)))
    shown = baseline_command(tiltgate, gateway.config_path)
    t.check("and the baseline set before it is in force",
            shown.returncode == 0 and abs(shown_x(shown.stdout) - 2.0) < 1e-3 and
            "set by" in shown.stdout, (shown.stdout, shown.stderr))
    t.check("/api/events filters: sensor, kind, from/to, limit; a bad value is a 400",
            len(events(gateway, "?limit=2")) == 2 and
            events(gateway, "?sensor=nobody") == [] and
            all(e["kind"] == "alarm" for e in events(gateway, "?kind=alarm")) and
            events(gateway, "?from=%d" % (int(time.time() * 1000) + 60000)) == [],
            events(gateway, "?limit=2"))
    try:
        urllib.request.urlopen("http://127.0.0.1:%d/api/events?from=yesterday" %
                               gateway.http_port, timeout=5)
        status = 200
    except urllib.error.HTTPError as e:
        status = e.code
    t.check("/api/events?from=yesterday is a 400", status == 400, status)
    t.check("the gateway stops cleanly", gateway.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("monitoring-events").run(scenario))
