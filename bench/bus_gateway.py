#!/usr/bin/env python3
"""The bus side of the gateway as a whole: `tiltgate run` polling simulated Rieker H6 sensors.

Every table runs the product as deployed: `tiltgate sim rieker` serves many addresses on one
pseudo-terminal, its replies paced at the baud rate (the request's own wire time included; the
simulator also waits its default 200 us "as fast as possible" reply latency before answering),
and `tiltgate run` polls them through its bus scheduler with every sensor at `poll_ms = 10`, so
the bus is saturated (but for one sensor at 125000 baud: poll_ms cannot go below 10, so one
sensor asks for only 100 polls/s, the "asked" column). Counters come from the HTTP API (`/api/sensors`).

1. Bus efficiency at 9600 and 125000 baud for 1, 10 and 60 sensors on one bus, against the
   wire limit (request bits + max(reply bits, the manual's 1 ms between master packets) per
   poll, as bench/bus_throughput.cpp computes it); polls/s is the median over consecutive
   windows of one gateway run. Fairness (10 and 60 sensors): the spread of the sensors' update
   rates over the whole measured time, as min/max and the coefficient of variation.
   At 125000 baud with 10 and 60 sensors, the tight master too (bench/tight_master.cpp: write
   the request, read exactly the reply, repeat), in the same run, in rounds: each round a
   gateway and its simulator started for one window (measured once every sensor answered, and
   0.5 s more) and stopped, and the tight master polling a fresh simulator started with the same
   options and addresses for as long, the gateway first in every other round. Both start
   afresh each round: a gateway stopped with SIGSTOP for the master's turn and continued ran
   some windows 20-40 % slow on the development machine, a fresh one at most 9 % (once in
   about 20 windows).
   Side by side: the same comparison with the two polling at the same time, each its own
   simulator, the tight master's window inside the gateway's; per round the ratio of the two,
   median and quartiles over the rounds. The machine's speed moves a poll's time by several
   per cent from one window to the next; measured at the same time, both see the same machine,
   and the ratio holds to a few tenths of a per cent where the rounds above spread by 5-10 %.
2. The same saturated bus (10 and 60 sensors, 125000 baud, the default `timeout_ms = 50`) idle and
   under a 64-client Modbus TCP flood (bench_modbus_load, function 04 x 10 on unit 1),
   alternating; polls/s medians, their ratio, and how often a sensor stopped answering (the
   gateway's "stopped answering" log line; the simulator never stops, so each one is false),
   summed over the rounds, with the reply time-outs (retried ones included) beside them.
   Each round is a fresh gateway's idle and flooded windows and a tight master's, as in 1;
   idle/tight and flooded/tight are ratios of medians.
3. Freshness: the time from a simulated angle change (`angle ADDRESS X Y` on `tiltgate sim
   rieker`'s standard input, timed from its "ok") to the new value read over Modbus (input
   register 4, angle_x_cdeg, read back to back by one client), for 1 and 10 sensors at poll_ms
   20 and 100 on a 125000-baud bus, against the poll period: median, p95 and the longest.
4. RSS and CPU of `tiltgate run` with 8 buses x 60 sensors (each bus its own simulator and
   `tcp_port`, unit ids 1..60 on each, the default `poll_ms = 100`): VmRSS after 10 s and CPU%
   over those 10 s (user + system time of the gateway process alone).

Usage: bench/bus_gateway.py [--quick] [--windows N] [--seconds S] [--build DIR]
"""
import argparse
import json
import os
import random
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile

# The TCP benchmark beside this script has the helpers both need.
from modbus_tcp_client import read_input
from tcp_throughput import cpu_seconds, free_port
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# Get Angle type 4: request 7 + 1 + 2 bytes, reply 7 + 8 + 2 bytes; 10 bits a byte (8N1).
REQUEST_BYTES, REPLY_BYTES, GAP_S = 10, 17, 0.001
SIM_LATENCY_S = 200e-6  # RiekerSimulatorOptions::reply_latency, which `tiltgate sim` keeps


def wire_limit(baud):
    return 1.0 / (REQUEST_BYTES * 10 / baud + max(REPLY_BYTES * 10 / baud, GAP_S))


_handed_out = set()


def distinct_port():
    """A free port not handed out before in this run: one gateway's listeners must all differ
    (free_port() alone can return a port twice, and the HTTP API then cannot bind)."""
    while True:
        port = free_port()
        if port not in _handed_out:
            _handed_out.add(port)
            return port


def rss_kib(pid, field="VmRSS"):
    """A process's resident size now (VmRSS), or at its peak so far (VmHWM), in KiB."""
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    return 0


def stop(process):
    if process.poll() is None:
        process.send_signal(signal.SIGTERM)
        try:
            process.wait(5)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def start_simulator(binary, link, baud, sensors, commands=False):
    """`tiltgate sim rieker` with H6 sensors at addresses 1..sensors on one pty (`link`), its
    replies paced at `baud`: the bus every table polls, the gateway's and the tight master's."""
    spec = ",".join(f"h6:{a}" for a in range(1, sensors + 1))
    sim = subprocess.Popen(
        [binary, "sim", "rieker", "--sensors", spec, "--link", link, "--pace-baud", str(baud)],
        stderr=subprocess.DEVNULL, text=True,
        stdin=subprocess.PIPE if commands else subprocess.DEVNULL,
        stdout=subprocess.PIPE if commands else subprocess.DEVNULL)
    if commands:
        sim.stdout.readline()  # the pty's path
    for _ in range(200):
        if os.path.exists(link):
            break
        time.sleep(0.05)
    return sim


def tight_master(binary, build, folder, baud, sensors, seconds):
    """bench_tight_master's polls/s and lost polls (time-outs, and bad replies) over `seconds`,
    round robin over addresses 1..sensors of a fresh simulator started with the gateway's
    options (start_simulator)."""
    sub = tempfile.mkdtemp(dir=folder)
    link = os.path.join(sub, "tty")
    sim = start_simulator(binary, link, baud, sensors)
    try:
        out = subprocess.run([os.path.join(build, "bench", "bench_tight_master"), link, str(baud),
                              str(seconds), f"1-{sensors}"],
                             stdout=subprocess.PIPE, text=True, check=True).stdout
    finally:
        stop(sim)
    fields = dict(item.split("=") for item in out.split() if "=" in item)
    # The plainest master has no late-reply guard: a reply that comes after its time-out is
    # read as the next request's and refused. More bad replies than time-outs would mean a
    # broken simulator, not a busy machine.
    timeouts, bad = int(fields["timeouts"]), int(fields["bad_replies"])
    if bad > timeouts:
        sys.exit(f"bench_tight_master read bad replies: {out.strip()}")
    return float(fields["polls_per_s"]), timeouts + bad


class Gateway:
    """Simulated buses (one `tiltgate sim rieker` each) and one `tiltgate run` polling them."""

    def __init__(self, binary, folder, baud, buses, sensors, poll_ms, own_ports=False,
                 commands=False, server_keys="", http_keys="", control_socket="",
                 first_sensor_keys=""):
        """commands: the simulators' standard input and output are pipes (sim_command());
        server_keys, http_keys: more [server] lines (writes = true), more [http] lines
        (users_file); control_socket: its path, "" off; poll_ms None: the default;
        first_sensor_keys: more lines for the first sensor of each bus (bench/bursts.py)."""
        self.sims = []
        self.http_port = distinct_port()
        self.modbus_port = distinct_port()
        config = [f"""[server]
listen = "127.0.0.1"
port = {self.modbus_port}
max_clients = 100
max_clients_per_host = 100
control_socket = "{control_socket}"
{server_keys}

[http]
listen = "127.0.0.1"
port = {self.http_port}
{http_keys}
"""]
        for b in range(buses):
            link = os.path.join(folder, f"tty{b}")
            self.sims.append(start_simulator(binary, link, baud, sensors, commands))
            config.append(f'[[bus]]\nname = "line{b}"\nport = "{link}"\nbaud = {baud}\n' +
                          (f"tcp_port = {distinct_port()}\n" if own_ports else ""))
            for a in range(1, sensors + 1):
                config.append(f'[[sensor]]\nname = "s{b}_{a}"\nbus = "line{b}"\nmodel = "h6"\n'
                              f"address = {a}\nunit_id = {a}\n" +
                              (f"poll_ms = {poll_ms}\n" if poll_ms else "") +
                              (first_sensor_keys + "\n" if a == 1 else ""))
        path = os.path.join(folder, "bench.toml")
        with open(path, "w") as f:
            f.write("\n".join(config))
        self.log_path = os.path.join(folder, "tiltgate.log")
        self.log = open(self.log_path, "w")
        self.started = time.monotonic()
        self.process = subprocess.Popen([binary, "run", "--config", path],
                                        stdout=self.log, stderr=subprocess.STDOUT)
        end = time.time() + 20
        while True:
            if self.process.poll() is not None:
                self.stop()  # the simulators too: nothing of a failed run is left running
                sys.exit(f"tiltgate run exited with status {self.process.returncode}; "
                         f"see {self.log_path}")
            try:
                # /healthz, not the API: with [http] users_file the API needs a session.
                urllib.request.urlopen(f"http://127.0.0.1:{self.http_port}/healthz",
                                       timeout=5).close()
                break
            except OSError:
                if time.time() > end:
                    self.stop()
                    sys.exit(f"tiltgate run did not serve HTTP; see {self.log_path}")
                time.sleep(0.05)

    def sensors(self):
        url = f"http://127.0.0.1:{self.http_port}/api/sensors"
        with urllib.request.urlopen(url, timeout=5) as reply:
            return json.load(reply)

    def polls(self):
        """Each sensor's polls_ok, and the time they were read."""
        sensors = self.sensors()
        return time.monotonic(), {s["name"]: s["polls_ok"] for s in sensors}

    def wait_all_polled(self, seconds=60):
        end = time.time() + seconds
        while time.time() < end:
            if all(s["polls_ok"] > 0 for s in self.sensors()):
                return
            time.sleep(0.1)
        sys.exit("not every sensor answered")

    def timeouts(self):
        return sum(s["failures"]["timeout"] for s in self.sensors())

    def stopped_answering(self):
        self.log.flush()
        with open(self.log_path) as f:
            return f.read().count("stopped answering")

    def sim_command(self, line, bus=0):
        """Sends one command to a simulator and waits for its answer."""
        sim = self.sims[bus]
        sim.stdin.write(line + "\n")
        sim.stdin.flush()
        answer = sim.stdout.readline().strip()
        if answer != "ok":
            sys.exit(f"tiltgate sim answered {answer!r} to {line!r}")

    def stop(self):
        stop(self.process)
        for sim in self.sims:
            stop(sim)
        self.log.close()


def rates(before, after):
    (t0, p0), (t1, p1) = before, after
    return {name: (p1[name] - p0[name]) / (t1 - t0) for name in p1}


def measured_windows(gateway, windows, window):
    """`windows` consecutive windows of `window` seconds, once every sensor answered and 0.5 s
    more: for each, the polls before and after, as Gateway.polls() gives them."""
    gateway.wait_all_polled()
    time.sleep(0.5)
    spans = []
    for _ in range(windows):
        before = gateway.polls()
        time.sleep(window)
        spans.append((before, gateway.polls()))
    return spans


def fresh_gateway_window(binary, folder, baud, count, window):
    """One window (measured_windows) of a gateway started for it and stopped after."""
    gateway = Gateway(binary, tempfile.mkdtemp(dir=folder), baud, 1, count, 10)
    try:
        return measured_windows(gateway, 1, window)[0]
    finally:
        gateway.stop()


def in_turn(round_, gateway_turn, master_turn):
    """A round's two turns, the gateway's first in even rounds and the tight master's in odd
    ones, so that neither is always measured on a machine the other just left."""
    for turn in (gateway_turn, master_turn) if round_ % 2 == 0 else (master_turn, gateway_turn):
        turn()


def efficiency(binary, folder, build, windows, seconds):
    print(f"Bus efficiency: `tiltgate run`, every sensor at poll_ms = 10 (the bus saturated); "
          f"polls/s is the median of {windows} windows, fairness over all of them; at 125000 "
          f"baud with 10 and 60 sensors each window is a fresh gateway's, alternating with one of "
          f"bench_tight_master on a fresh simulator, the median of those beside it")
    print()
    print("| baud | sensors | asked (polls/s) | wire limit (polls/s) | median polls/s | ratio "
          "| overhead per poll (us) | ratio without the simulator's 200 us | per-sensor min/max "
          "| per-sensor CV | tight master polls/s | gateway / tight master |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for baud in (9600, 125000):
        for count in (1, 10, 60):
            # The comparison: a saturated bus at the factory rate.
            with_tight = baud == 125000 and count > 1
            sub = tempfile.mkdtemp(dir=folder)
            # At 9600 baud 60 sensors get under one poll each a second: windows long enough
            # for about ten polls per sensor each, so the spread is not rounding.
            window = max(seconds, min(10.0, 10 * count / wire_limit(baud)))
            spans, tight = [], []
            if with_tight:
                # Each round a fresh gateway and a fresh tight master: neither is measured as
                # the one that keeps running.
                for round_ in range(windows):
                    in_turn(round_,
                            lambda: spans.append(
                                fresh_gateway_window(binary, sub, baud, count, window)),
                            lambda: tight.append(
                                tight_master(binary, build, sub, baud, count, window)[0]))
            else:
                gateway = Gateway(binary, sub, baud, 1, count, 10)
                try:
                    spans = measured_windows(gateway, windows, window)
                finally:
                    gateway.stop()
            totals = [sum(rates(a, b).values()) for a, b in spans]
            median = statistics.median(totals)
            limit = wire_limit(baud)
            # One sensor at 125000 baud asks for fewer polls than the wire carries: no overhead
            # to compute there.
            overhead = f"{(1 / median - 1 / limit) * 1e6:.0f}" if count * 100 > limit else "-"
            with_sim = 1 / (1 / limit + SIM_LATENCY_S)
            fair_min_max = fair_cv = "-"
            if count > 1:
                # Each sensor's polls over the time of all windows (not the pauses between).
                span_time = sum(b[0] - a[0] for a, b in spans)
                per_sensor = [sum(b[1][name] - a[1][name] for a, b in spans) / span_time
                              for name in spans[-1][1][1]]
                mean = statistics.mean(per_sensor)
                fair_min_max = f"{min(per_sensor) / max(per_sensor):.2f}"
                fair_cv = f"{statistics.pstdev(per_sensor) / mean:.3f}"
            tight_cells = "- | -"
            if tight:
                reference = statistics.median(tight)
                tight_cells = f"{reference:.1f} | {median / reference:.3f}"
            print(f"| {baud} | {count} | {count * 100} | {limit:.1f} | {median:.1f} | {median / limit:.2f} | "
                  f"{overhead} | {median / with_sim:.2f} | {fair_min_max} | {fair_cv} | "
                  f"{tight_cells} |", flush=True)
    print()


def side_by_side(binary, folder, build, rounds, seconds):
    print(f"Side by side: a fresh gateway and bench_tight_master polling at the same time, each "
          f"its own simulator, 125000 baud, poll_ms = 10; {rounds} rounds of {seconds:g} s; "
          f"per round gateway polls/s over the master's, their median and quartiles")
    print()
    print("| sensors | gateway polls/s | tight master polls/s | gateway / tight master "
          "| quartiles | lowest round |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: |")
    for count in (10, 60):
        sub = tempfile.mkdtemp(dir=folder)
        gateway_rates, master_rates = [], []
        for _ in range(rounds):
            gateway = Gateway(binary, tempfile.mkdtemp(dir=sub), 125000, 1, count, 10)
            try:
                gateway.wait_all_polled()
                time.sleep(0.5)
                before = gateway.polls()
                master_rates.append(tight_master(binary, build, sub, 125000, count, seconds)[0])
                gateway_rates.append(sum(rates(before, gateway.polls()).values()))
            finally:
                gateway.stop()
        ratios = [g / m for g, m in zip(gateway_rates, master_rates)]
        quartiles = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else ratios * 3
        print(f"| {count} | {statistics.median(gateway_rates):.1f} | "
              f"{statistics.median(master_rates):.1f} | {statistics.median(ratios):.4f} | "
              f"{quartiles[0]:.4f}-{quartiles[2]:.4f} | {min(ratios):.4f} |", flush=True)
    print()


def flood(binary, folder, build, rounds, seconds):
    load = os.path.join(build, "bench", "bench_modbus_load")
    print(f"Bus under a Modbus TCP flood: 10 and 60 sensors at 125000 baud, poll_ms = 10, "
          f"timeout_ms = 50; {rounds} rounds of {seconds:g} s idle, {seconds:g} s with 64 clients "
          f"(function 04 x 10, unit 1), each round a fresh gateway, and {seconds:g} s of "
          f"bench_tight_master before or after it; medians")
    print()
    print("| sensors | bus polls/s idle | bus polls/s flooded | ratio | tight master polls/s "
          "| idle / tight | flooded / tight | Modbus req/s during the flood "
          "| stopped answering idle | stopped answering flooded | time-outs idle | time-outs flooded "
          "| tight master time-outs and late replies |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for count in (10, 60):
        sub = tempfile.mkdtemp(dir=folder)
        gateway_rounds, tight, tight_lost = [], [], []

        def master_turn():
            polls_per_s, lost = tight_master(binary, build, sub, 125000, count, seconds)
            tight.append(polls_per_s)
            tight_lost.append(lost)

        for round_ in range(rounds):
            in_turn(round_, lambda: gateway_rounds.append(flood_round(binary, sub, load, count, seconds)),
                    master_turn)
        def median(key):
            return statistics.median(r[key] for r in gateway_rounds)

        def total(key):
            return sum(r[key] for r in gateway_rounds)

        i, f, t = median("idle"), median("flooded"), statistics.median(tight)
        print(f"| {count} | {i:.1f} | {f:.1f} | {f / i:.3f} | {t:.1f} | {i / t:.3f} | {f / t:.3f} | "
              f"{median('requests'):.0f} | {total('offline_idle')} | {total('offline_flooded')} | "
              f"{total('timeouts_idle')} | {total('timeouts_flooded')} | {sum(tight_lost)} |",
              flush=True)
    print()


def flood_round(binary, folder, load, count, seconds):
    """A fresh gateway's idle window and its window under the 64-client flood: polls/s of each,
    the flood's Modbus req/s, and the false offlines and reply time-outs in each."""
    gateway = Gateway(binary, tempfile.mkdtemp(dir=folder), 125000, 1, count, 10)
    try:
        gateway.wait_all_polled()
        time.sleep(0.5)
        before, offline, timeouts = gateway.polls(), gateway.stopped_answering(), gateway.timeouts()
        time.sleep(seconds)
        after = gateway.polls()
        result = {"idle": sum(rates(before, after).values()),
                  "offline_idle": gateway.stopped_answering() - offline,
                  "timeouts_idle": gateway.timeouts() - timeouts}
        offline, timeouts = gateway.stopped_answering(), gateway.timeouts()
        flood = subprocess.Popen([load, "--port", str(gateway.modbus_port), "--clients", "64",
                                  "--function", "4", "--quantity", "10", "--unit", "1",
                                  "--seconds", str(seconds)],
                                 stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        time.sleep(0.3)  # the clients connected and the flood under way
        before = gateway.polls()
        time.sleep(max(0.5, seconds - 0.6))
        after = gateway.polls()
        out, _ = flood.communicate()
        fields = dict(item.split("=") for item in out.split() if "=" in item)
        result.update({"flooded": sum(rates(before, after).values()),
                       "requests": float(fields.get("req_per_s", 0)),
                       "offline_flooded": gateway.stopped_answering() - offline,
                       "timeouts_flooded": gateway.timeouts() - timeouts})
        return result
    finally:
        gateway.stop()


def read_angle_x_cdeg(connection):
    """Unit 1's input register 4 (angle_x_cdeg) as a signed number, or None for an exception
    reply (a stale or offline sensor's, say)."""
    try:
        (word,) = read_input(connection, 1, 4, 1)
    except ValueError:
        return None
    except ConnectionError:
        sys.exit("the gateway closed the Modbus connection")
    return word - 0x10000 if word & 0x8000 else word


def freshness(binary, folder, changes):
    print(f"Freshness: a simulated angle change to the new value read over Modbus, 125000 baud, "
          f"{changes} changes each, times in ms")
    print()
    print("| sensors | poll_ms | median | p95 | longest | median / poll period |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: |")
    for count, poll_ms in ((1, 20), (1, 100), (10, 20), (10, 100)):
        sub = tempfile.mkdtemp(dir=folder)
        gateway = Gateway(binary, sub, 125000, 1, count, poll_ms, commands=True)
        delays = []
        chance = random.Random(poll_ms * 1000 + count)  # the same waits in every run
        try:
            gateway.wait_all_polled()
            with socket.create_connection(("127.0.0.1", gateway.modbus_port)) as connection:
                connection.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                for i in range(changes):
                    # Distinct values, each a new one.
                    cdeg = 1000 + 37 * i if i % 2 else -1000 - 37 * i
                    # The read that saw the last change came just after a poll: wait a random
                    # part of the period, or every change would land just after a poll.
                    time.sleep(chance.uniform(0, poll_ms / 1000))
                    gateway.sim_command(f"angle 1 {cdeg / 100:.2f} 0")
                    changed = time.monotonic()
                    while read_angle_x_cdeg(connection) != cdeg:
                        if time.monotonic() - changed > 5:
                            sys.exit("the new angle never reached Modbus")
                    delays.append((time.monotonic() - changed) * 1000)
        finally:
            gateway.stop()
        delays.sort()
        median = statistics.median(delays)
        p95 = delays[min(len(delays) - 1, int(0.95 * len(delays)))]
        print(f"| {count} | {poll_ms} | {median:.1f} | {p95:.1f} | {delays[-1]:.1f} | "
              f"{median / poll_ms:.2f} |", flush=True)
    print()


def scale(binary, folder, seconds):
    print("Scale: `tiltgate run` with 8 buses x 60 simulated H6 at 125000 baud (each bus its own "
          "tcp_port, poll_ms = 100); the gateway process alone")
    print()
    print("| sensors | VmRSS after start (MiB) | VmRSS after {0:g} s (MiB) | CPU % over {0:g} s "
          "| sensors polled | polls/s (all buses) |".format(seconds))
    print("| ---: | ---: | ---: | ---: | ---: | ---: |")
    sub = tempfile.mkdtemp(dir=folder)
    gateway = Gateway(binary, sub, 125000, 8, 60, 100, own_ports=True)
    try:
        pid = gateway.process.pid
        rss_start = rss_kib(pid)
        cpu_start, t_start = cpu_seconds(pid), time.monotonic()
        before = gateway.polls()
        time.sleep(max(0.0, seconds - (time.monotonic() - gateway.started)))
        cpu = (cpu_seconds(pid) - cpu_start) / (time.monotonic() - t_start) * 100
        rss = rss_kib(pid)
        after = gateway.polls()
        polled = sum(1 for n in after[1] if after[1][n] > 0)
        total = sum(rates(before, after).values())
    finally:
        gateway.stop()
    print(f"| {len(after[1])} | {rss_start / 1024:.1f} | {rss / 1024:.1f} | {cpu:.0f} | {polled} | "
          f"{total:.0f} |")
    print()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--windows", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--quick", action="store_true", help="1 window of 1.5 s each")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--only", choices=["efficiency", "side", "flood", "freshness", "scale"],
                        help="one table only")
    args = parser.parse_args()
    if args.quick:
        args.windows, args.seconds = 1, 1.5
    binary = os.path.join(args.build, "tiltgate")
    folder = tempfile.mkdtemp(prefix="tiltgate-busbench-")
    try:
        print(f"({os.cpu_count()} cores)\n")
        wanted = lambda table: args.only in (None, table)
        if wanted("efficiency"):
            efficiency(binary, folder, args.build, args.windows, args.seconds)
        if wanted("side"):
            # Short windows are enough: the two share every moment of the machine.
            side_by_side(binary, folder, args.build, max(args.windows, 5), args.seconds)
        if wanted("flood"):
            flood(binary, folder, args.build, args.windows, args.seconds)
        if wanted("freshness"):
            freshness(binary, folder, 10 if args.quick else 40)
        if wanted("scale"):
            scale(binary, folder, 10.0)
    finally:
        if not os.environ.get("KEEP_DIR"):
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
