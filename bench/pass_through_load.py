#!/usr/bin/env python3
"""Pass-through writes and their audit records, side by side with the binary before them.

Issue 52 made every request passed through to a device that may change it ([[bus]]
pass_through: FC 5, 6, 15, 16, 22, 23 ...) a record of the audit trail, handed to the trail's
writer thread. This bench runs two gateway binaries, the new one and the one before (default
/work/base/build/tiltgate, commit d7deef2: no pass-through audit, no request admission), at
the same time, each on its own simulated Modbus RTU line (`tiltgate sim modbus-rtu` of the
new binary for both, replies paced at the line's 115200 baud): slave 17 a cached sensor
(unit 1, polled every 100 ms), slave 30 passed through (unit 30), `[server] writes = true`
and `state_dir` in a temporary folder. The new binary's config raises `max_requests_per_s`
and `max_client_requests_per_s` to 1000000 (the old one refuses those keys: each config is
written for what its binary's `check` accepts).

Every round starts both gateways afresh, and runs each scenario on both at once: the
pass-through client goes from one gateway to the other every --seconds/--slices (A B A B ...,
--seconds on each in all; the first of a round goes last in the next), so both are measured
on the same moments of a shared machine:
- one client sends FC 06 (holding register 0, 2 and 3 in turn) to unit 30, one at a time,
  each the moment the previous answer is in; then the same client with FC 03 (holding
  register 0, one register), passed through and not audited: the reference in the same run;
- both again while N other clients (bench_modbus_load, one process per gateway, --load 8,32)
  read each gateway's cached sensor (FC 04 x 10 on unit 1) flat out, the whole scenario long.

Per scenario: the pass-through client's median round trip and requests/s, the gateway's CPU
time (user + system, /proc/PID/stat) per request it answered in the scenario, net of what it
spends at rest (measured without clients at the start of each round: its polls of the cached
sensor), so idle rows show the CPU of one passed-through request and its audit record (under
load the readers' requests are most of them), and the readers' requests/s. Each figure is the
median over the rounds, each ratio new/old the median of the rounds' own ratios. The 06/03
columns divide a binary's FC 06 round trip by its FC 03 one in the same round: the audit's
cost against the unaudited pass-through. Then per binary its peak RSS (VmHWM, at the end of
each round) and the audit records in its state_dir (`tiltgate audit --json`) against the FC 06
writes it answered: the new binary must show one record for each (exit status 1 otherwise).
The load average before and after is printed with the table: on a shared machine, the ratios
are what counts.

About 4 minutes with the defaults (5 rounds of a rest window and 6 scenarios x 2 binaries,
3 s each).

Usage: bench/pass_through_load.py [--new PATH] [--old PATH] [--sim PATH] [--rounds N]
                                  [--seconds S] [--slices N] [--load 8,32] [--quick]
                                  [--build DIR]
"""
import argparse
import json
import os
import shutil
import socket
import statistics
import struct
import subprocess
import sys
import tempfile
import time

from bus_gateway import distinct_port, rss_kib, stop
from modbus_tcp_client import modbus_call
from tcp_throughput import cpu_seconds, wait_for_port

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

BAUD = 115200
# The trail keeps some 15,000 records on disk (docs/operations.md, "The audit trail"): a round
# with more writes than this is not counted against it.
MOST_WRITES_COUNTED = 12000
CACHED_SLAVE, CACHED_UNIT, PASSED_SLAVE = 17, 1, 30
PROFILE = os.path.join(ROOT, "examples", "devices", "rtu-inclinometer.toml")
# The new binary's keys the old one does not know (issue 51's request admission).
ADMISSION_KEYS = "max_requests_per_s = 1000000\nmax_client_requests_per_s = 1000000\n"


class PassThroughGateway:
    """A simulated Modbus RTU line and one `tiltgate run` on it: slave CACHED_SLAVE a cached
    sensor at unit CACHED_UNIT, slave PASSED_SLAVE passed through."""

    def __init__(self, binary, sim_binary, folder, max_clients):
        self.binary = binary
        self.state_dir = os.path.join(folder, "state")
        link = os.path.join(folder, "tty")
        self.sim = subprocess.Popen(
            [sim_binary, "sim", "modbus-rtu", "--sensors",
             f"modbus-rtu:{CACHED_SLAVE},modbus-rtu:{PASSED_SLAVE}", "--link", link,
             "--pace-baud", str(BAUD)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(200):
            if os.path.exists(link):
                break
            time.sleep(0.05)
        try:
            self.start_gateway(binary, folder, link, max_clients)
        except BaseException:
            stop(self.sim)  # nothing of a failed start is left running
            raise

    def start_gateway(self, binary, folder, link, max_clients):
        self.port = distinct_port()
        config = os.path.join(folder, "bench.toml")
        # offline = "last": a poll the busy machine answers late must not turn the readers'
        # requests into 0x0B, which bench_modbus_load counts as errors.
        text = f"""[server]
listen = "127.0.0.1"
port = {self.port}
max_clients = {max_clients}
max_clients_per_host = {max_clients}
control_socket = ""
writes = true
state_dir = "{self.state_dir}"
{ADMISSION_KEYS}
[http]
enabled = false

[[bus]]
name = "rtu"
port = "{link}"
protocol = "modbus-rtu"
baud = {BAUD}
pass_through = [{PASSED_SLAVE}]

[[sensor]]
name = "cached"
bus = "rtu"
model = "modbus-rtu"
address = {CACHED_SLAVE}
unit_id = {CACHED_UNIT}
offline = "last"
device = "{PROFILE}"
"""
        with open(config, "w") as f:
            f.write(text)
        check = subprocess.run([binary, "check", "--config", config], capture_output=True,
                               text=True)
        if "max_requests_per_s: unknown key" in check.stdout + check.stderr:
            with open(config, "w") as f:
                f.write(text.replace(ADMISSION_KEYS, ""))
        self.log = open(os.path.join(folder, "tiltgate.log"), "w")
        self.process = subprocess.Popen([binary, "run", "--config", config],
                                        stdout=self.log, stderr=subprocess.STDOUT)
        wait_for_port(self.port, self.process, f"{binary} run")
        self.wait_cached_answering()

    def wait_cached_answering(self, seconds=20):
        with connect(self.port) as sock:
            end = time.time() + seconds
            while time.time() < end:
                reply = modbus_call(sock, CACHED_UNIT, struct.pack(">BHH", 4, 0, 10))
                if not reply[0] & 0x80:
                    return
                time.sleep(0.1)
        stop(self.process)
        sys.exit(f"{self.binary}: the cached sensor never answered")

    def peak_rss_kib(self):
        return rss_kib(self.process.pid, "VmHWM")

    def audit_records(self, setting):
        """The records of `setting` in the trail (read once the gateway has stopped)."""
        out = subprocess.run([self.binary, "audit", "--state-dir", self.state_dir, "--limit", "0",
                              "--setting", setting, "--json"],
                             capture_output=True, text=True, check=True).stdout
        return len(json.loads(out))

    def stop(self):
        stop(self.process)
        stop(self.sim)
        self.log.close()


def connect(port):
    sock = socket.create_connection(("127.0.0.1", port), timeout=10)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return sock


def pass_through_client(sock, function, seconds, times):
    """FC 06 or FC 03 to the passed-through unit on `sock`, one at a time, for `seconds`, each
    round trip (s) appended to `times`: the exception answers among them."""
    exceptions = 0
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        value = 2 + len(times) % 2  # the profile's filter_level takes 1..8
        pdu = struct.pack(">BHH", function, 0, value if function == 6 else 1)
        sent = time.monotonic()
        reply = modbus_call(sock, PASSED_SLAVE, pdu)
        times.append(time.monotonic() - sent)
        if reply[0] & 0x80:
            exceptions += 1
        elif function == 6 and reply != pdu:
            sys.exit(f"FC 06 answered {reply.hex()} to {pdu.hex()}")
    return exceptions


def start_readers(load_binary, gateway, readers, seconds):
    return subprocess.Popen([load_binary, "--port", str(gateway.port), "--clients", str(readers),
                             "--function", "4", "--quantity", "10", "--unit", str(CACHED_UNIT),
                             "--seconds", f"{seconds:g}"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def readers_result(load, gateway):
    """bench_modbus_load's requests and requests/s; any error ends the bench."""
    out, err = load.communicate()
    fields = dict(item.split("=") for item in out.split() if "=" in item)
    if load.returncode != 0 or int(fields.get("errors", "1")) != 0:
        sys.exit(f"the readers of {gateway.binary} failed: {out}{err}")
    return int(fields["requests"]), float(fields["req_per_s"])


def scenario(gateways, order, load_binary, readers, function, args, rest):
    """One scenario on every gateway at once: the readers (if any) on each for the whole of
    it, and the pass-through client going from one gateway to the next every slice (A B A B
    ...), --seconds on each in all. Per gateway its figures; CPU net of `rest` (CPU seconds a
    second at rest)."""
    slices = args.slices
    cpu_before = {name: cpu_seconds(g.process.pid) for name, g in gateways.items()}
    started = time.monotonic()
    loads = {}
    if readers:
        for name, g in gateways.items():
            loads[name] = start_readers(load_binary, g, readers,
                                        len(gateways) * args.seconds + 0.6)
        time.sleep(0.3)  # the readers connected and under way
    times = {name: [] for name in gateways}
    spent = {name: 0.0 for name in gateways}
    exceptions = {name: 0 for name in gateways}
    sockets = {name: connect(g.port) for name, g in gateways.items()}
    try:
        for _ in range(slices):
            for name in order:
                begun = time.monotonic()
                exceptions[name] += pass_through_client(sockets[name], function,
                                                        args.seconds / slices, times[name])
                spent[name] += time.monotonic() - begun
    finally:
        for sock in sockets.values():
            sock.close()
    results = {}
    for name, g in gateways.items():
        reader_requests, reader_rate = readers_result(loads[name], g) if readers else (0, 0.0)
        span = time.monotonic() - started
        cpu = cpu_seconds(g.process.pid) - cpu_before[name] - rest[name] * span
        results[name] = {"rtt_ms": statistics.median(times[name]) * 1000,
                         "req_per_s": len(times[name]) / spent[name],
                         "cpu_us": cpu * 1e6 / (len(times[name]) + reader_requests),
                         "readers_per_s": reader_rate, "requests": len(times[name]),
                         "exceptions": exceptions[name]}
    return results


def run_round(round_, binaries, args, folder, scenarios, load_binary):
    """Fresh gateways for every binary, then each scenario on them (scenario()); the figures
    per (binary, readers, function), and per binary its peak RSS and (after it stopped) its
    audit records of FC 06 and the FC 06 writes it answered."""
    max_clients = max(readers for readers, _ in scenarios) + 8
    gateways = {}
    try:
        for name, binary in binaries:
            sub = os.path.join(folder, f"{name}-{round_}")
            os.mkdir(sub)
            gateways[name] = PassThroughGateway(binary, args.sim, sub, max_clients)
        # Each gateway's CPU at rest: both measured over the same seconds.
        before = {name: cpu_seconds(g.process.pid) for name, g in gateways.items()}
        time.sleep(args.seconds)
        rest = {name: (cpu_seconds(g.process.pid) - before[name]) / args.seconds
                for name, g in gateways.items()}
        order = [name for name, _ in binaries]
        if round_ % 2:
            order.reverse()  # the first of a round goes last in the next
        windows = {}
        for readers, function in scenarios:
            results = scenario(gateways, order, load_binary, readers, function, args, rest)
            for name, figures in results.items():
                windows[(name, readers, function)] = figures
        rss = {name: g.peak_rss_kib() for name, g in gateways.items()}
    finally:
        for g in gateways.values():
            g.stop()
    writes = {name: sum(w["requests"] for (n, _, f), w in windows.items() if n == name and f == 6)
              for name in gateways}
    records = {name: g.audit_records("function 06") if writes[name] <= MOST_WRITES_COUNTED
               else None for name, g in gateways.items()}
    return windows, rss, writes, records


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--new", default=os.path.join(ROOT, "build", "tiltgate"))
    parser.add_argument("--old", default="/work/base/build/tiltgate")
    parser.add_argument("--sim", help="the simulator's tiltgate (default: --new)")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--load", default="8,32", help="reader counts under load")
    parser.add_argument("--slices", type=int, default=6,
                        help="turns of each binary in a scenario (the client goes A B A B ...)")
    parser.add_argument("--quick", action="store_true", help="1 round of 1.5 s windows")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    args = parser.parse_args()
    if args.quick:
        args.rounds, args.seconds = 1, 1.5
    args.sim = args.sim or args.new
    for binary in (args.new, args.old):
        if not os.access(binary, os.X_OK):
            sys.exit(f"{binary}: not an executable (--new, --old)")
    load_binary = os.path.join(args.build, "bench", "bench_modbus_load")
    binaries = [("new", args.new), ("old", args.old)]
    scenarios = [(readers, function) for readers in [0] + [int(n) for n in args.load.split(",")]
                 for function in (6, 3)]
    load_before = os.getloadavg()
    folder = tempfile.mkdtemp(prefix="tiltgate-ptbench-")
    rounds = []
    try:
        for round_ in range(args.rounds):
            rounds.append(run_round(round_, binaries, args, folder, scenarios, load_binary))
    finally:
        if not os.environ.get("KEEP_DIR"):
            shutil.rmtree(folder, ignore_errors=True)
    report(rounds, scenarios, args, load_before, os.getloadavg())


def report(rounds, scenarios, args, load_before, load_after):
    loads = lambda l: " / ".join(f"{x:.2f}" for x in l)
    print(f"Pass-through on a simulated Modbus RTU line at {BAUD} baud: new {args.new}, old "
          f"{args.old}; {args.rounds} round(s) of {args.seconds:g} s windows, medians "
          f"({os.cpu_count()} cores; load average before {loads(load_before)}, after "
          f"{loads(load_after)})")
    print()
    print("| scenario | round trip new (ms) | old (ms) | new/old | req/s new | old | new/old "
          "| CPU us/req (net of rest) new | old | new/old | 06/03 new | 06/03 old "
          "| readers req/s new | old | new/old |")
    print("| --- " + "| ---: " * 14 + "|")
    for readers, function in scenarios:
        w = lambda r, name, f=function: r[0][(name, readers, f)]
        med = lambda name, key: statistics.median(w(r, name)[key] for r in rounds)
        ratio = lambda key: statistics.median(w(r, "new")[key] / max(w(r, "old")[key], 1e-9)
                                              for r in rounds)
        # A binary's FC 06 round trip over its FC 03 one in the same round.
        per_reference = lambda name: statistics.median(
            w(r, name, 6)["rtt_ms"] / w(r, name, 3)["rtt_ms"] for r in rounds)
        label = f"FC {function:02d}, " + (f"{readers} readers" if readers else "idle")
        row = f"| {label} "
        for key, fmt in (("rtt_ms", ".2f"), ("req_per_s", ".0f"), ("cpu_us", ".1f")):
            row += f"| {med('new', key):{fmt}} | {med('old', key):{fmt}} | {ratio(key):.3f} "
        row += (f"| {per_reference('new'):.3f} | {per_reference('old'):.3f} " if function == 6
                else "| - | - ")
        row += (f"| {med('new', 'readers_per_s'):.0f} | {med('old', 'readers_per_s'):.0f} "
                f"| {ratio('readers_per_s'):.3f} |" if readers else "| - | - | - |")
        print(row)
    print()
    # Only the rounds whose writes the trail can hold all (MOST_WRITES_COUNTED) are counted.
    counted = [r for r in rounds if None not in r[3].values()]
    print(f"| binary | peak RSS (MiB) | FC 06 answered (rounds counted: {len(counted)}) "
          "| audit records of FC 06 | exception answers to the pass-through client |")
    print("| --- | ---: | ---: | ---: | ---: |")
    for name in ("new", "old"):
        rss = statistics.median(r[1][name] for r in rounds) / 1024
        writes = sum(r[2][name] for r in counted)
        records = sum(r[3][name] for r in counted)
        exceptions = sum(w["exceptions"] for r in rounds for (n, _, _), w in r[0].items()
                         if n == name)
        print(f"| {name} | {rss:.1f} | {writes} | {records} | {exceptions} |")
    new_writes, new_records = (sum(r[i]["new"] for r in counted) for i in (2, 3))
    if new_records != new_writes:
        sys.exit(f"\nThe new binary's trail holds {new_records} records of FC 06 for "
                 f"{new_writes} writes answered")


if __name__ == "__main__":
    main()
