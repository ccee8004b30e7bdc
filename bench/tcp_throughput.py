#!/usr/bin/env python3
"""TCP throughput and latency of tiltgate's Modbus TCP side against the plainest libmodbus
server (bench/reference_server.cpp), in the same run.

For 1, 8, 32 and 64 clients x function 03 / 04 x 10 / 125 registers, the servers take turns in
rounds, each turn bench_modbus_load for a few seconds, each round in another order (the first
of one round goes last in the next); the table shows medians over the rounds: requests/s of
each, the ratio tiltgate / reference, and the p50 / p99 / p99.9 latency of each (us), and each
server's CPU time per request (us; user + system, from /proc, so it holds up better than
requests/s when other work shares the cores) with its ratio to the reference's. That ratio is
the median of each round's own ratio: the development machine's speed moves by steps over
minutes, and a step between two rounds then moves both servers of a ratio alike.

tiltgate runs as `tiltgate run` on one simulated Rieker H6 (`tiltgate sim rieker`, polled every
50 ms at 125000 baud, so the bus works meanwhile as in a plant), unit 1, with a map that extends
the built-in one to 125 input registers (0..124) and 125 holding registers (0..124), so both
quantities read mapped registers. The reference maps 200 of each.

Usage: bench/tcp_throughput.py [--runs N] [--seconds S] [--quick] [--clients 1,8,...]
                               [--tiltgate PATH] [--also NAME=PATH ...] [--threads 1,2]
                               [--floor] [--build DIR]
--also adds another tiltgate binary (an older build, say) to the same alternation; --threads
adds the gateway with those [server] threads; --floor adds bench/floor_server.cpp, the least a
server can spend on a read on this machine (one epoll loop, canned replies, no checks).
"""
import argparse
import os
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for_port(port, process, what, seconds=10):
    end = time.time() + seconds
    while time.time() < end:
        if process.poll() is not None:
            sys.exit(f"{what} exited with status {process.returncode}")
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.2):
                return
        except OSError:
            time.sleep(0.05)
    sys.exit(f"{what} did not listen on port {port}")


def bench_map():
    """Input and holding registers 0..124: the built-in map, then uint16 points after it."""
    lines = ['extends = "default"', ""]
    for table, first in (("input", 38), ("holding", 8)):
        for address in range(first, 125):
            lines += ["[[point]]", f'name = "bench_{table}_{address}"', f'table = "{table}"',
                      f"address = {address}", 'type = "uint16"', 'source = "sample_seq"', ""]
    return "\n".join(lines)


class Tiltgate:
    def __init__(self, binary, folder, clients, threads=None):
        self.folder = folder
        self.port = free_port()
        link = os.path.join(folder, "ttyBENCH")
        self.sim = subprocess.Popen([binary, "sim", "rieker", "--sensors", "h6:223", "--link", link],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(100):
            if os.path.exists(link):
                break
            time.sleep(0.05)
        with open(os.path.join(folder, "bench-map.toml"), "w") as f:
            f.write(bench_map())
        # The bus keeps the default timeout_ms (50): it runs on its own thread, which the
        # flood of TCP clients does not hold up. The sensor reads its last value while offline
        # (`offline = "last"`): on a busy virtual machine the simulator, a process beside the
        # load generator, now and then answers 100 ms late, and one such poll would otherwise
        # turn a read into 0x0B, which the load generator counts as an error and which ends
        # the run. bench/bus_gateway.py counts those moments ("stopped answering").
        config = os.path.join(folder, "bench.toml")
        with open(config, "w") as f:
            f.write(f"""[server]
listen = "127.0.0.1"
port = {self.port}
max_clients = {max(clients, 32)}
max_clients_per_host = {max(clients, 32)}
control_socket = ""
{f"threads = {threads}" if threads else ""}

[http]
enabled = false

[[bus]]
name = "line1"
port = "{link}"
protocol = "rieker"

[[sensor]]
name = "bench"
bus = "line1"
model = "h6"
address = 223
unit_id = 1
poll_ms = 50
offline = "last"
map = "bench-map.toml"
""")
        self.log = open(os.path.join(folder, "tiltgate.log"), "w")
        self.process = subprocess.Popen([binary, "run", "--config", config],
                                        stdout=self.log, stderr=subprocess.STDOUT)
        wait_for_port(self.port, self.process, f"{binary} run")

    def stop(self):
        for p in (self.process, self.sim):
            p.send_signal(signal.SIGTERM)
        for p in (self.process, self.sim):
            try:
                p.wait(5)
            except subprocess.TimeoutExpired:
                p.kill()
        self.log.close()


class Reference:
    """The plainest libmodbus server, or the floor server: a binary that takes its port."""

    def __init__(self, binary):
        self.port = free_port()
        self.process = subprocess.Popen([binary, str(self.port)], stdout=subprocess.DEVNULL)
        wait_for_port(self.port, self.process, binary)

    def stop(self):
        self.process.send_signal(signal.SIGTERM)
        try:
            self.process.wait(5)
        except subprocess.TimeoutExpired:
            self.process.kill()


def cpu_seconds(pid):
    """User + system CPU time of a process so far (/proc/PID/stat fields 14 and 15)."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def load(server, load_binary, clients, function, quantity, seconds):
    port = server.port
    cpu_before = cpu_seconds(server.process.pid)
    result = subprocess.run([load_binary, "--port", str(port), "--clients", str(clients),
                             "--function", str(function), "--quantity", str(quantity),
                             "--seconds", str(seconds), "--unit", "1"],
                            capture_output=True, text=True)
    fields = dict(item.split("=") for item in result.stdout.split())
    if result.returncode != 0 or int(fields.get("errors", "1")) != 0:
        sys.exit(f"load against port {port} failed: {result.stdout}{result.stderr}")
    values = {k: float(v) for k, v in fields.items()}
    # The server's CPU time per request: steadier than requests/s on a busy machine.
    values["cpu_us"] = (cpu_seconds(server.process.pid) - cpu_before) * 1e6 / max(values["requests"], 1)
    return values


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--quick", action="store_true", help="1 run of 1 s each")
    parser.add_argument("--clients", default="1,8,32,64")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--tiltgate")
    parser.add_argument("--also", action="append", default=[], metavar="NAME=PATH")
    parser.add_argument("--threads", help="also run the gateway with these [server] threads, "
                                          "e.g. 1,2 (the default run has one per core)")
    parser.add_argument("--floor", action="store_true",
                        help="also run bench_floor_server, the least a server can spend on a read")
    args = parser.parse_args()
    if args.quick:
        args.runs, args.seconds = 1, 1.0
    load_binary = os.path.join(args.build, "bench", "bench_modbus_load")
    reference_binary = os.path.join(args.build, "bench", "bench_reference_server")
    floor_binary = os.path.join(args.build, "bench", "bench_floor_server")
    servers = [("reference", None), ("tiltgate", args.tiltgate or os.path.join(args.build, "tiltgate"))]
    servers += [tuple(a.split("=", 1)) for a in args.also]
    threads = {}  # server name -> [server] threads
    for n in (args.threads.split(",") if args.threads else []):
        servers.append((f"tiltgate t{n}", servers[1][1]))
        threads[f"tiltgate t{n}"] = int(n)
    if args.floor:
        servers.append(("floor", floor_binary))
    plain = {"reference": reference_binary, "floor": floor_binary}  # Reference-like servers
    client_counts = [int(c) for c in args.clients.split(",")]

    folder = tempfile.mkdtemp(prefix="tiltgate-bench-")
    running = {}
    try:
        for name, binary in servers:
            sub = os.path.join(folder, name)
            os.mkdir(sub)
            running[name] = (Reference(plain[name]) if name in plain
                             else Tiltgate(binary, sub, max(client_counts), threads.get(name)))
        time.sleep(1)  # the sensor's first readings
        print(f"Modbus TCP, medians of {args.runs} runs of {args.seconds:g} s "
              f"({os.cpu_count()} cores); req/s, and latency p50 / p99 / p99.9 in us")
        others = [name for name, _ in servers if name != "reference"]
        header = "| clients | function | registers | reference req/s |"
        for name in others:
            header += f" {name} req/s | {name}/reference |"
        header += " reference p50/p99/p99.9 |" + "".join(f" {n} p50/p99/p99.9 |" for n in others)
        header += " CPU us/req " + " / ".join(["reference"] + others) + " |"
        header += "".join(f" {n} CPU/reference |" for n in others)
        print(header)
        print("|" + " ---: |" * (header.count("|") - 1))
        for clients in client_counts:
            for function in (3, 4):
                for quantity in (10, 125):
                    results = {name: [] for name, _ in servers}
                    names = [name for name, _ in servers]
                    for run in range(args.runs):
                        for name in names[run % len(names):] + names[:run % len(names)]:
                            results[name].append(load(running[name], load_binary, clients,
                                                      function, quantity, args.seconds))
                    med = {name: {k: statistics.median(r[k] for r in rs) for k in rs[0]}
                           for name, rs in results.items()}
                    ref = med["reference"]
                    row = f"| {clients} | {function:02d} | {quantity} | {ref['req_per_s']:.0f} |"
                    for name in others:
                        row += f" {med[name]['req_per_s']:.0f} | {med[name]['req_per_s'] / ref['req_per_s']:.2f} |"
                    for name in ["reference"] + others:
                        m = med[name]
                        row += f" {m['p50_us']:.0f} / {m['p99_us']:.0f} / {m['p999_us']:.0f} |"
                    row += " " + " / ".join(f"{med[n]['cpu_us']:.1f}" for n in ["reference"] + others) + " |"
                    for name in others:
                        paired = [r["cpu_us"] / max(q["cpu_us"], 1e-9)
                                  for r, q in zip(results[name], results["reference"])]
                        row += f" {statistics.median(paired):.2f} |"
                    print(row, flush=True)
    finally:
        for server in running.values():
            server.stop()
        if not os.environ.get("KEEP_DIR"):
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
