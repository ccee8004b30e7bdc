#!/usr/bin/env python3
"""Monitoring at the edge (issue 57, items 4, 7 and 8): a sensor's long record and its triggered
bursts, from outside. A simulated mast drifts slowly under `tiltgate sim rieker`; the gateway
keeps min/mean/max per second ([record] interval_s = 1) and GET
/api/sensors/NAME/history.csv?from=&to= gives them in order, each row's min <= mean <= max and
its count of samples what a second of 100 ms polls brings; the rows are there after a SIGKILL.
A step past the alarm starts a burst: the sensor is polled back to back for burst_s, the other
sensor on the line keeps its own period, and the burst's CSV holds pre_trigger_s of samples
before the trigger; `tiltgate check` prints the record's disk budget, and `tiltgate history`
reads the record from the state directory, `tiltgate bursts` the bursts.

Usage: /usr/bin/python3 monitoring_record_test.py path/to/tiltgate
"""
import csv
import io
import json
import os
import subprocess
import sys
import time
import urllib.error
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Gateway, Simulator  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

SENSORS = {"mast": {"model": "h6", "address": 223, "unit_id": 1},
           "pier": {"model": "h6", "address": 224, "unit_id": 2}}
POLL_MS = 100
# Under a sanitizer (scripts/sanitize sets ASAN_OPTIONS or TSAN_OPTIONS) the gateway polls
# slower: the counts get more slack, the behaviour is checked the same.
SANITIZED = "ASAN_OPTIONS" in os.environ or "TSAN_OPTIONS" in os.environ
BURST_S = 2
PRE_S = 1


def write_config(gateway, sim, state_dir):
    lines = ["[server]", 'listen = "127.0.0.1"', "port = %d" % gateway.modbus_port,
             'control_socket = ""', 'state_dir = "%s"' % state_dir, "",
             "[http]", 'listen = "127.0.0.1"', "port = %d" % gateway.http_port, "",
             "[record]", "interval_s = 1", "keep_days = 2", "",
             "[[bus]]", 'name = "line1"', 'port = "%s"' % sim.link, 'protocol = "rieker"', "",
             "[[sensor]]", 'name = "mast"', 'bus = "line1"', 'model = "h6"', "address = 223",
             "unit_id = 1", "poll_ms = %d" % POLL_MS, "burst_s = %d" % BURST_S,
             "pre_trigger_s = %d" % PRE_S, "alarms = { x_high = 2.0 }", "",
             "[[sensor]]", 'name = "pier"', 'bus = "line1"', 'model = "h6"', "address = 224",
             "unit_id = 2", "poll_ms = %d" % POLL_MS]
    with open(gateway.config_path, "w") as f:
        f.write("\n".join(lines) + "\n")


def get(gateway, path):
    return urllib.request.urlopen("http://127.0.0.1:%d%s" % (gateway.http_port, path),
                                  timeout=10).read().decode()


def rows(gateway, sensor, since_ms):
    text = get(gateway, "/api/sensors/%s/history.csv?from=%d" % (sensor, since_ms))
    return list(csv.DictReader(io.StringIO(text)))


def drift(sim, start, per_s, seconds, step=0.05):
    """The mast tilting slowly: x from `start` at `per_s` degrees a second."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < seconds:
        sim.command("angle 223 %.5f 0.0" % (start + per_s * (time.monotonic() - t0)))
        time.sleep(step)


def scenario(t):
    tiltgate, _ = arguments()
    sim = Simulator(tiltgate, t.dir, sensors=SENSORS)
    state_dir = os.path.join(t.dir, "state")
    gateway = Gateway(tiltgate, t.dir, sim, None)
    t.logs.append(("gateway", gateway.log_path))
    write_config(gateway, sim, state_dir)
    checked = subprocess.run([tiltgate, "check", "--config", gateway.config_path],
                             capture_output=True, text=True, timeout=30)
    t.check("tiltgate check prints the long record's disk budget",
            checked.returncode == 0 and
            "long record: 2 sensors x 2 days at 1 s: " in checked.stdout, checked.stdout)
    sim.command("angle 223 0.5 0.0")
    sim.command("angle 224 -0.25 0.0")
    started_ms = int(time.time() * 1000)
    gateway.start()
    drift(sim, 0.5, 0.05, 5.0)
    wait_until(lambda: len(rows(gateway, "mast", started_ms)) >= 4, 5)
    before = rows(gateway, "mast", started_ms)
    t.check("a row a second, in time order", len(before) >= 4 and
            [r["time"] for r in before] == sorted(r["time"] for r in before), before)
    full = [r for r in before[1:-1]]  # the first may be short (the gateway started in it)
    t.check("each full second sums up about 10 readings of a 100 ms poll",
            full and all((3 if SANITIZED else 8) <= int(r["samples"]) <= 12 for r in full),
            [r["samples"] for r in before])
    t.check("min <= mean <= max, and x drifts upward row by row",
            all(float(r["x_min"]) <= float(r["x_mean"]) <= float(r["x_max"]) for r in before) and
            float(before[-1]["x_mean"]) > float(before[0]["x_mean"]),
            [(r["x_min"], r["x_mean"], r["x_max"]) for r in before])
    t.check("a single value column left empty where the sensor has none (temperature)",
            all(r["temperature_mean"] == "" for r in before), before[0])

    gateway.kill()
    gateway.start()
    after = rows(gateway, "mast", started_ms)
    kept = [r["time"] for r in before]
    t.check("after a SIGKILL every row written before it is still there",
            [r["time"] for r in after][:len(kept)] == kept, (kept, [r["time"] for r in after]))
    cli = subprocess.run([tiltgate, "history", "--config", gateway.config_path, "--sensor", "mast",
                          "--from", str(started_ms)], capture_output=True, text=True, timeout=30)
    t.check("tiltgate history gives the same rows from the state directory",
            cli.returncode == 0 and
            [r["time"] for r in csv.DictReader(io.StringIO(cli.stdout))][:len(kept)] == kept,
            (cli.returncode, cli.stderr, cli.stdout[:300]))
    bad = subprocess.run([tiltgate, "history", "--config", gateway.config_path, "--sensor", "mast",
                          "--from", "soon"], capture_output=True, text=True, timeout=30)
    t.check("tiltgate history --from soon is a usage error (exit 2) that says why",
            bad.returncode == 2 and "--from" in bad.stderr, (bad.returncode, bad.stderr))
    try:
        get(gateway, "/api/sensors/mast/history.csv?from=never")
        status = 200
    except urllib.error.HTTPError as e:
        status = e.code
    t.check("a bad from= is a 400", status == 400, status)

    # A step past x_high: a burst of BURST_S s, polled back to back.
    pier_before = gateway.sensor_api("pier")["polls_ok"]
    mast_before = gateway.sensor_api("mast")["polls_ok"]
    drift(sim, 1.0, 0.0, 1.5)
    sim.command("angle 223 2.5 0.0")
    time.sleep(BURST_S + 1.5)
    mast_polls = gateway.sensor_api("mast")["polls_ok"] - mast_before
    pier_polls = gateway.sensor_api("pier")["polls_ok"] - pier_before
    elapsed_polls = (1.5 + BURST_S + 1.5) * 1000 / POLL_MS
    t.check("the burst polls the mast well beyond its period (3x more polls at least)",
            mast_polls >= (1.5 if SANITIZED else 3) * elapsed_polls, (mast_polls, elapsed_polls))
    t.check("the pier on the same line keeps its period meanwhile",
            pier_polls >= (0.4 if SANITIZED else 0.8) * elapsed_polls, (pier_polls, elapsed_polls))
    bursts = json.loads(get(gateway, "/api/sensors/mast/bursts"))
    t.check("one burst is listed", len(bursts) == 1, bursts)
    if bursts:
        text = get(gateway, "/api/sensors/mast/bursts/%s.csv" % bursts[0]["id"])
        burst = list(csv.DictReader(io.StringIO(text)))
        phases = [r["phase"] for r in burst]
        t.check("its CSV: pre_trigger_s of samples before, the trigger, then the burst",
                phases.count("trigger") == 1 and
                (1 if SANITIZED else PRE_S * 1000 / POLL_MS - 2) <= phases.count("pre") <=
                PRE_S * 1000 / POLL_MS + 2 and
                phases.count("burst") >= (1 if SANITIZED else 2) * BURST_S * 1000 / POLL_MS,
                (phases.count("pre"), phases.count("burst")))
        t.check("the trigger is the first reading past x_high",
                float(burst[phases.index("trigger")]["x"]) > 2.0 and
                all(float(r["x"]) < 2.0 for r in burst if r["phase"] == "pre"), burst[:15])
        listed = subprocess.run([tiltgate, "bursts", "--config", gateway.config_path,
                                 "--sensor", "mast"], capture_output=True, text=True, timeout=30)
        t.check("tiltgate bursts lists it by its id", listed.returncode == 0 and
                bursts[0]["id"] in listed.stdout, listed.stdout + listed.stderr)
        last = subprocess.run([tiltgate, "bursts", "--config", gateway.config_path,
                               "--sensor", "mast", "--id", "last"],
                              capture_output=True, text=True, timeout=30)
        t.check("tiltgate bursts --id last writes the CSV the console downloads",
                last.returncode == 0 and last.stdout.startswith(
                    "time,unix_ms,phase,x,y,tilt,relative_x,relative_y,displacement_mm,"
                    "temperature,alarms,clock_synchronised") and
                len(last.stdout.splitlines()) >= len(burst), last.stderr or last.stdout[:300])
        wrong = subprocess.run([tiltgate, "bursts", "--config", gateway.config_path,
                                "--sensor", "mast", "--id", "../../etc/passwd"],
                               capture_output=True, text=True, timeout=30)
        t.check("a burst id that is a path: exit 2 saying what an id looks like",
                wrong.returncode == 2 and "is no burst id" in wrong.stderr, wrong.stderr)
    kinds = [(e["kind"], e.get("state")) for e in
             json.loads(get(gateway, "/api/events?kind=burst"))]
    t.check("the burst's start and end are events", kinds == [("burst", "end"), ("burst", "start")],
            kinds)
    t.check("the gateway stops cleanly", gateway.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("monitoring-record").run(scenario))
