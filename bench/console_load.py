#!/usr/bin/env python3
"""What the web console costs the buses and the Modbus clients (issue 42: "a console user
refreshing and a scan through the console leave the bus at >= 0.99 of its idle polls/s and the
Modbus p99 unchanged").

One `tiltgate run` (bench/bus_gateway.py's Gateway) polls simulated Rieker H6 sensors on one
pseudo-terminal at 125000 baud, every sensor at poll_ms = 50 (--poll-ms; the H6's documented 20 polls/s:
the bus about half used, as a plant runs it), with [http] users_file and [server]
control_socket set. A Modbus TCP client reads the sensors' input registers 0..7 at a steady
rate the whole time, each unit in turn on one connection, timing every read. Three phases, run
in rounds in the same gateway, each round a window of each phase, the order turned by one each
round so that no phase is always measured on a machine another just left:

1. idle: the polls and the Modbus client; nobody on the console.
2. console: the same plus console users (admin accounts made with `tiltgate user add`) doing
   what the page does: GET /api/sensors and /api/buses every 0.4 s (the page's POLL_MS),
   /api/sensors/NAME/history every second (the page redraws an open graph every 2 s), each on
   one kept-alive connection, as a browser keeps it; each user logs out and in again every 5 s
   (a login checks an argon2id hash: about 25 ms on the console's own thread).
3. scan: the same plus a scan through the console, repeated: POST /api/buses/line0/scan over
   addresses where no sensor is (each probe a time-out), GET .../scan for progress every 0.5 s
   (the page's SCAN_POLL_MS) until it ends, then the next.

Every process of load (the Modbus client, each console user, the scanner) is a process of its
own, so that none of them waits for another's turn at Python's lock and the Modbus times are the
gateway's. Polls/s: sensor polls that brought a reading (tiltgate_polls_total, result "ok", from
/metrics, which needs no session) over each window. Modbus p50 and p99: of each window's reads;
the table has the medians over the windows, and "within noise" means a phase's median p99 is no
higher than the highest p99 of an idle window.

Usage: bench/console_load.py [--quick] [--rounds N] [--seconds S] [--poll-ms MS] [--build DIR]
"""
import argparse
import http.client
import json
import multiprocessing
import os
import queue
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

from bus_gateway import Gateway
from modbus_tcp_client import read_input

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

BAUD, SENSORS = 125000, 10
MODBUS_READS_PER_S = 200
USERS = 3
PAGE_POLL_S, HISTORY_S, LOGIN_AGAIN_S, SCAN_POLL_S = 0.4, 1.0, 5.0, 0.5
SCAN_FROM, SCAN_TO = 200, 229  # no sensor there: every probe a time-out
PASSWORD = "bench-console-password"
PHASES = ("idle", "console", "scan")


def bus_counters(http_port):
    """From /metrics (which needs no session): the sensor polls that brought a reading, all
    sensors together, and the seconds the bus spent in transactions (the scan's probes too)."""
    with urllib.request.urlopen(f"http://127.0.0.1:{http_port}/metrics", timeout=5) as reply:
        lines = reply.read().decode().splitlines()
    polls = sum(float(line.rsplit(" ", 1)[1]) for line in lines
                if line.startswith("tiltgate_polls_total{") and 'result="ok"' in line)
    busy = sum(float(line.rsplit(" ", 1)[1]) for line in lines
               if line.startswith("tiltgate_bus_busy_seconds_total{"))
    return polls, busy


def add_users(binary, users_file, names):
    for name in names:
        subprocess.run([binary, "user", "add", name, "--role", "admin", "--users-file",
                        users_file], input=PASSWORD + "\n", text=True, check=True,
                       stdout=subprocess.DEVNULL)


class Console:
    """One console user's browser: a kept-alive connection, its session cookie and CSRF token."""

    def __init__(self, port, user):
        self.port, self.user = port, user
        self.connection = None
        self.cookie = self.csrf = ""

    def call(self, method, path, body=None):
        """The reply's status and JSON; a connection the server closed is opened again once."""
        headers = {"Cookie": self.cookie} if self.cookie else {}
        data = None
        if method != "GET":
            headers.update({"Content-Type": "application/json", "X-CSRF-Token": self.csrf})
            data = json.dumps(body if body is not None else {})
        for attempt in (0, 1):
            if self.connection is None:
                self.connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=30)
            try:
                self.connection.request(method, path, body=data, headers=headers)
                reply = self.connection.getresponse()
                payload = reply.read()
                break
            except (http.client.HTTPException, ConnectionError):
                self.connection.close()
                self.connection = None
                if attempt:
                    raise
        cookie = reply.getheader("Set-Cookie")
        if cookie:
            self.cookie = cookie.split(";", 1)[0]
        return reply.status, (json.loads(payload) if payload else None)

    def login(self):
        if self.cookie:
            self.call("POST", "/api/logout")
            self.cookie = ""
        status, answer = self.call("POST", "/api/login", {"user": self.user, "password": PASSWORD})
        if status != 200:
            raise RuntimeError(f"login as {self.user}: {status} {answer}")
        self.csrf = answer["csrf"]

    def get(self, path):
        status, answer = self.call("GET", path)
        if status != 200:
            raise RuntimeError(f"GET {path}: {status} {answer}")
        return answer


def modbus_client(port, stop, results):
    """Reads input registers 0..7 of units 1..SENSORS in turn at MODBUS_READS_PER_S; puts the
    list of (start, milliseconds) of every read in `results` when `stop` is set."""
    times = []
    with socket.create_connection(("127.0.0.1", port)) as connection:
        connection.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        period = 1.0 / MODBUS_READS_PER_S
        due = time.monotonic()
        unit = 0
        while not stop.is_set():
            now = time.monotonic()
            if due > now:
                time.sleep(due - now)
            # A read that comes late is not made up with a burst: the rate stays steady.
            due = max(due + period, time.monotonic() - period)
            unit = unit % SENSORS + 1
            start = time.monotonic()
            try:
                read_input(connection, unit, 0, 8)
            except ValueError:  # an exception reply (0x0B: the sensor's reading not fresh)
                times.append((start, None))
                continue
            times.append((start, (time.monotonic() - start) * 1000))
    results.put(times)


def console_user(port, user, run, stop, results):
    """While `run` is set, refreshes the console's API as the page does; counts its requests and
    the time each took (ms)."""
    browser = Console(port, user)
    took, logins = [], 0
    next_history = next_login = 0.0
    sensor = 0
    while not stop.is_set():
        if not run.wait(0.05):
            continue
        start = time.monotonic()
        if start >= next_login:
            browser.login()
            logins += 1
            next_login = start + LOGIN_AGAIN_S
        for path in ("/api/sensors", "/api/buses"):
            begun = time.monotonic()
            browser.get(path)
            took.append((time.monotonic() - begun) * 1000)
        if start >= next_history:
            sensor = sensor % SENSORS + 1
            begun = time.monotonic()
            browser.get(f"/api/sensors/s0_{sensor}/history")
            took.append((time.monotonic() - begun) * 1000)
            next_history = start + HISTORY_S
        time.sleep(max(0.0, start + PAGE_POLL_S - time.monotonic()))
    results.put({"user": user, "took": took, "logins": logins})


def scanner(port, user, run, stop, quiet, results):
    """While `run` is set, scans addresses SCAN_FROM..SCAN_TO through the console, one scan after
    the other, polling its progress as the page does; sets `quiet` whenever no scan runs."""
    browser = Console(port, user)
    browser.login()
    scans, errors = [], []
    quiet.set()
    while not stop.is_set():
        if not run.wait(0.05):
            continue
        quiet.clear()
        started = time.monotonic()
        status, answer = browser.call("POST", "/api/buses/line0/scan",
                                      {"from": SCAN_FROM, "to": SCAN_TO})
        if status == 401:  # the session expired while the other phases ran
            browser.login()
            status, answer = browser.call("POST", "/api/buses/line0/scan",
                                          {"from": SCAN_FROM, "to": SCAN_TO})
        if status != 202:
            errors.append(f"POST scan: {status} {answer}")
        while True:
            time.sleep(SCAN_POLL_S)
            state = browser.get("/api/buses/line0/scan")
            if not state["running"]:
                break
        scans.append(time.monotonic() - started)
        if not (state["error"] or "").startswith("no sensor answered") or state["found"]:
            errors.append(f"scan ended: {state['error']!r}, found {len(state['found'])}")
        quiet.set()
    results.put({"user": user, "scans": scans, "errors": errors})


def window(http_port, seconds):
    """Polls/s over `seconds` from now, the window's start and end, and the bus's utilisation."""
    t0, (p0, b0) = time.monotonic(), bus_counters(http_port)
    time.sleep(seconds)
    t1, (p1, b1) = time.monotonic(), bus_counters(http_port)
    return (p1 - p0) / (t1 - t0), t0, t1, (b1 - b0) / (t1 - t0)


def collect(results, workers):
    """The next result a load process put in `results`; exits when one of them failed."""
    while True:
        try:
            return results.get(timeout=1)
        except queue.Empty:
            failed = [w for w in workers if w.exitcode not in (None, 0)]
            if failed:
                sys.exit(f"{len(failed)} load process(es) failed; see above")


def percentile(values, q):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def measure(binary, folder, rounds, seconds, poll_ms):
    users_file = os.path.join(folder, "users")
    names = [f"bench{i}" for i in range(1, USERS + 1)] + ["scanner"]
    add_users(binary, users_file, names)
    gateway = Gateway(binary, folder, BAUD, 1, SENSORS, poll_ms,
                      server_keys=f'state_dir = "{folder}/state"',
                      http_keys=f'users_file = "{users_file}"',
                      control_socket=os.path.join(folder, "control.sock"))
    fork = multiprocessing.get_context("fork")
    stop, browse, scan, quiet = fork.Event(), fork.Event(), fork.Event(), fork.Event()
    modbus_results, console_results = fork.Queue(), fork.Queue()
    workers = [fork.Process(target=modbus_client, args=(gateway.modbus_port, stop, modbus_results))]
    workers += [fork.Process(target=console_user, args=(gateway.http_port, name, browse, stop,
                                                        console_results))
                for name in names[:USERS]]
    workers.append(fork.Process(target=scanner, args=(gateway.http_port, names[-1], scan, stop,
                                                      quiet, console_results)))
    windows = {phase: [] for phase in PHASES}
    try:
        # Every sensor answering and the poll rate settled before the first window.
        end = time.time() + 30
        while bus_counters(gateway.http_port)[0] < SENSORS * 10:
            if time.time() > end:
                sys.exit("the sensors were not polled")
            time.sleep(0.1)
        for worker in workers:
            worker.start()
        time.sleep(1.0)
        for round_ in range(rounds):
            for phase in PHASES[round_ % 3:] + PHASES[:round_ % 3]:
                if phase in ("console", "scan"):
                    browse.set()
                if phase == "scan":
                    scan.set()
                time.sleep(1.0)  # the load under way (the first scan's command started)
                windows[phase].append(window(gateway.http_port, seconds))
                browse.clear()
                scan.clear()
                if not quiet.wait(60):
                    sys.exit("a scan through the console never ended")
                time.sleep(0.5)
        stop.set()
        browse.set()  # a user waiting for its turn sees the stop
        modbus_times = collect(modbus_results, workers)
        console = [collect(console_results, workers) for _ in names]
        for worker in workers:
            worker.join(10)
        failed = [w for w in workers if w.exitcode != 0]
        if failed:
            sys.exit(f"{len(failed)} load process(es) failed; see above")
    finally:
        stop.set()
        for worker in workers:
            if worker.is_alive():
                worker.terminate()
        gateway.stop()
    return windows, modbus_times, console


def report(windows, modbus_times, console, rounds, seconds, poll_ms):
    def latencies(t0, t1):
        return [ms for start, ms in modbus_times if t0 <= start < t1 and ms is not None]

    exceptions = sum(1 for _, ms in modbus_times if ms is None)

    rows = {}
    for phase in PHASES:
        polls = [w[0] for w in windows[phase]]
        p50 = [percentile(latencies(t0, t1), 0.50) for _, t0, t1, _ in windows[phase]]
        p99 = [percentile(latencies(t0, t1), 0.99) for _, t0, t1, _ in windows[phase]]
        rows[phase] = {"polls": statistics.median(polls), "p50": statistics.median(p50),
                       "busy": statistics.median(w[3] for w in windows[phase]),
                       "p99": statistics.median(p99), "p99s": p99,
                       "reads": sum(len(latencies(t0, t1)) for _, t0, t1, _ in windows[phase]),
                       "exceptions": sum(1 for _, t0, t1, _ in windows[phase]
                                         for start, ms in modbus_times
                                         if t0 <= start < t1 and ms is None)}
    idle = rows["idle"]
    print(f"Web console load: {SENSORS} x H6 at {BAUD} baud, poll_ms = {poll_ms}; a Modbus client "
          f"reading input registers 0..7 at {MODBUS_READS_PER_S}/s; {USERS} console users "
          f"refreshing as the page does (logging in again every {LOGIN_AGAIN_S:g} s); scans of "
          f"addresses {SCAN_FROM}..{SCAN_TO} through the console, one after the other; "
          f"{rounds} rounds of a {seconds:g} s window of each phase; medians over the windows")
    print()
    print("| phase | bus polls/s (median) | ratio to idle | Modbus p50 (ms) | Modbus p99 (ms) "
          "| p99 / idle p99 |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for phase in PHASES:
        row = rows[phase]
        print(f"| {phase} | {row['polls']:.1f} | {row['polls'] / idle['polls']:.3f} | "
              f"{row['p50']:.3f} | {row['p99']:.3f} | {row['p99'] / idle['p99']:.2f} |")
    print()
    requests = [ms for c in console if "took" in c for ms in c["took"]]
    logins = sum(c.get("logins", 0) for c in console)
    scans = [c for c in console if "scans" in c]
    all_scans = [d for c in scans for d in c["scans"]]
    print(f"Console requests: {len(requests)} (p50 {percentile(requests, 0.5):.1f} ms, "
          f"p99 {percentile(requests, 0.99):.1f} ms), {logins} logins; scans through the "
          f"console: {len(all_scans)} (median {statistics.median(all_scans or [0]):.2f} s from "
          f"POST to the progress poll that saw it end); Modbus reads in the windows: "
          + ", ".join(f"{p} {rows[p]['reads']}" for p in PHASES)
          + f"; idle windows' p99: {min(idle['p99s']):.3f}-{max(idle['p99s']):.3f} ms; bus "
          f"utilisation (median): " + ", ".join(f"{p} {rows[p]['busy']:.2f}" for p in PHASES)
          + f"; Modbus exception replies over the whole run: {exceptions}, in the windows: "
          + ", ".join(f"{p} {rows[p]['exceptions']}" for p in PHASES))
    for phase in PHASES:
        print(f"{phase} windows' polls/s: "
              + " ".join(f"{w[0]:.1f}" for w in windows[phase]))
    for c in scans:
        for error in c["errors"][:5]:
            print(f"scan error: {error}")
    print()
    for phase in ("console", "scan"):
        row = rows[phase]
        polls_ok = row["polls"] >= 0.99 * idle["polls"]
        p99_ok = row["p99"] <= max(idle["p99s"])
        print(f"{phase}: bus polls/s {row['polls'] / idle['polls']:.3f} x idle "
              f"({'>=' if polls_ok else 'below'} 0.99); Modbus p99 {row['p99']:.3f} ms against "
              f"idle {idle['p99']:.3f} ({'within' if p99_ok else 'above'} the idle windows' "
              f"spread)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--quick", action="store_true", help="2 rounds of 2.5 s windows")
    parser.add_argument("--poll-ms", type=int, default=50,
                        help="every sensor's poll_ms (10: the bus saturated)")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    args = parser.parse_args()
    if args.quick:
        args.rounds, args.seconds = 2, 2.5
    binary = os.path.join(args.build, "tiltgate")
    folder = tempfile.mkdtemp(prefix="tiltgate-console-load-")
    try:
        print(f"({os.cpu_count()} cores)\n")
        windows, modbus_times, console = measure(binary, folder, args.rounds, args.seconds,
                                                 args.poll_ms)
        report(windows, modbus_times, console, args.rounds, args.seconds, args.poll_ms)
    finally:
        if not os.environ.get("KEEP_DIR"):
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
