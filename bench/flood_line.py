#!/usr/bin/env python3
"""A healthy line under a flood on every door (issue 51: "no flood of requests ever makes a
healthy sensor look dead").

One `tiltgate run` (bench/bus_gateway.py's Gateway) polls ten simulated Rieker H6 on one
pseudo-terminal at 125000 baud, their replies paced at the baud rate, every sensor at
poll_ms = 50 (the H6's documented 20 polls/s: 200 polls/s asked of a line that carries about
390), with the web console (`[http] users_file`), the MQTT feed and a Sparkplug B edge node on
(both to a mosquitto of the bench's own), every limit at its default. Then, for 0, 1, 4, 8, 32
and 64 Modbus clients, each a process of its own (bench_modbus_load, one connection, function
04 x 10 of one of the ten units, each request sent the moment the previous answer is in), for a
window of --seconds, while 16 console sessions (each a process: logged in, GET /api/sensors
every 100 ms on a kept-alive connection) read on. Each row is a fresh gateway and simulator.
Its table:

- bus polls/s (tiltgate_polls_total, result "ok") over the window, and against the row without
  clients;
- the longest reply in the window, as the bound of the reply-time histogram every reply was
  within (tiltgate_sensor_reply_seconds: from the end of the request to the reply's last byte,
  as the line waited for it), the longest since the gateway started (slowest_reply_ms, the
  start's logins and births included), and the reply waits this machine held back
  (tiltgate_bus_machine_held_total) or gave up (..._overloaded_total);
- exception answers to the Modbus clients (healthy sensors: the target is 0 in every row), and
  console reads that showed a sensor offline or stale;
- the Modbus requests answered a second, and the gateway's CPU time (user + system, /proc) per
  answered request against the plainest libmodbus server's (bench/reference_server.cpp) under
  the same clients in the same round, the two in turn; "net" takes off what the gateway spends
  without clients (its polls, console, MQTT and Sparkplug), measured in the row with 0 clients.
  The gateway answers at most its request rate ([server] max_requests_per_s), and a server's
  CPU per request depends on how busy it is (a server flat out takes many requests per
  wake-up; one held to a rate wakes for each), so the last two columns hold the gateway's net
  figure against libmodbus asked the gateway's own req/s by the same clients (each paced, in
  the same round).

--rounds N repeats every row N times; the table has the medians (the longest reply: the
longest). Prints one Markdown table. About 5 minutes a round with 10 s windows.

Usage: bench/flood_line.py [--quick] [--rounds N] [--seconds S] [--clients 0,1,4,...]
                           [--tiltgate PATH] [--build DIR]
"""
import argparse
import multiprocessing
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

from bus_gateway import Gateway, distinct_port, stop
from console_load import Console, PASSWORD, add_users

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

BAUD, SENSORS, POLL_MS = 125000, 10, 50
CONSOLE_SESSIONS, CONSOLE_PERIOD_S = 16, 0.1
WARM_UP_S = 2.0


def metrics(http_port):
    """/metrics as {name{labels}: value}."""
    with urllib.request.urlopen(f"http://127.0.0.1:{http_port}/metrics", timeout=10) as reply:
        lines = reply.read().decode().splitlines()
    values = {}
    for line in lines:
        if line and not line.startswith("#"):
            name, value = line.rsplit(" ", 1)
            values[name] = float(value)
    return values


def total(values, prefix, label=""):
    return sum(v for k, v in values.items() if k.startswith(prefix) and label in k)


def longest_reply_bound(before, after):
    """The smallest bound of tiltgate_sensor_reply_seconds (ms) that every reply of every sensor
    between the two /metrics reads was within; None when there was none."""
    deltas = {}  # le -> replies within it, all sensors
    for key, value in after.items():
        if key.startswith("tiltgate_sensor_reply_seconds_bucket{"):
            le = key.split('le="', 1)[1].split('"', 1)[0]
            deltas[le] = deltas.get(le, 0) + value - before.get(key, 0)
    every = deltas.get("+Inf", 0)
    if not every:
        return None
    for le in sorted((le for le in deltas if le != "+Inf"), key=float):
        if deltas[le] == every:
            return float(le) * 1000
    return float("inf")


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def start_broker(folder):
    port = distinct_port()
    config = os.path.join(folder, "mosquitto.conf")
    with open(config, "w") as f:
        f.write(f"listener {port} 127.0.0.1\nallow_anonymous true\npersistence false\n"
                "user root\n")
    broker = subprocess.Popen([shutil.which("mosquitto") or "/usr/sbin/mosquitto", "-c", config],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(0.3)
    return broker, port


def console_session(port, user, stop_event, results):
    """Logs in, then reads /api/sensors every CONSOLE_PERIOD_S until stopped; counts its reads
    and those that showed a sensor offline or stale."""
    browser = Console(port, user)
    browser.login()
    reads = unhealthy = 0
    due = time.monotonic()
    while not stop_event.is_set():
        due += CONSOLE_PERIOD_S
        sensors = browser.get("/api/sensors")
        reads += 1
        if any(not s["online"] or s["stale"] for s in sensors):
            unhealthy += 1
        time.sleep(max(0.0, due - time.monotonic()))
    results.put((reads, unhealthy))


def flood(load_binary, port, clients, seconds, rate=0.0):
    """`clients` load processes for `seconds`, flat out or each sending `rate` requests a
    second: answered, exceptions, errors."""
    pace = ["--rate", f"{rate:.1f}"] if rate > 0 else []
    processes = [subprocess.Popen(
        [load_binary, "--port", str(port), "--clients", "1", "--function", "4", "--quantity",
         "10", "--unit", str(i % SENSORS + 1), "--seconds", str(seconds), "--count-exceptions"]
        + pace, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        for i in range(clients)]
    answered = exceptions = errors = 0
    for p in processes:
        out, _ = p.communicate()
        fields = dict(item.split("=") for item in out.split()) if out.strip() else {}
        answered += int(fields.get("requests", 0))
        exceptions += int(fields.get("exceptions", 0))
        errors += int(fields.get("errors", 1))
    return answered, exceptions, errors


def gateway_row(binary, build, folder, clients, seconds):
    sub = tempfile.mkdtemp(dir=folder)
    users_file = os.path.join(sub, "users")
    names = [f"user{i}" for i in range(CONSOLE_SESSIONS)]
    add_users(binary, users_file, names)
    broker, broker_port = start_broker(sub)
    # The 16 sessions all come from this machine: each keeps its connection.
    tables = (f'users_file = "{users_file}"\nmax_clients_per_host = {CONSOLE_SESSIONS}\n\n'
              f'[mqtt]\nhost = "127.0.0.1"\nport = {broker_port}\n\n'
              f'[sparkplug]\nhost = "127.0.0.1"\nport = {broker_port}\ngroup_id = "bench"\n'
              f'edge_node_id = "flood"\n')
    gateway = Gateway(binary, sub, BAUD, 1, SENSORS, POLL_MS,
                      server_keys=f'state_dir = "{sub}"', http_keys=tables)
    stop_event = multiprocessing.Event()
    results = multiprocessing.Queue()
    sessions = [multiprocessing.Process(target=console_session,
                                        args=(gateway.http_port, name, stop_event, results))
                for name in names]
    try:
        for s in sessions:
            s.start()
        time.sleep(WARM_UP_S)
        before, cpu_before, t0 = metrics(gateway.http_port), cpu_seconds(gateway.process.pid), time.monotonic()
        if clients:
            answered, exceptions, errors = flood(os.path.join(build, "bench", "bench_modbus_load"),
                                                 gateway.modbus_port, clients, seconds)
        else:
            time.sleep(seconds)
            answered = exceptions = errors = 0
        after, cpu_after, t1 = metrics(gateway.http_port), cpu_seconds(gateway.process.pid), time.monotonic()
        stop_event.set()
        reads = unhealthy = 0
        for _ in sessions:
            r, u = results.get(timeout=30)
            reads, unhealthy = reads + r, unhealthy + u
        reader = Console(gateway.http_port, names[0])  # with users_file the API needs a session
        reader.login()
        sensors = reader.get("/api/sensors")
        stopped_answering = gateway.stopped_answering()
    finally:
        stop_event.set()
        for s in sessions:
            s.join(10)
        gateway.stop()
        stop(broker)
    elapsed = t1 - t0
    polls = lambda m: total(m, "tiltgate_polls_total{", 'result="ok"')
    return {
        "polls_per_s": (polls(after) - polls(before)) / elapsed,
        "slowest_ms": max(s["slowest_reply_ms"] for s in sensors),
        "window_bound_ms": longest_reply_bound(before, after),
        "held": total(after, "tiltgate_bus_machine_held_total"),
        "overloaded": total(after, "tiltgate_bus_overloaded_total"),
        "exceptions": exceptions, "errors": errors,
        "console_reads": reads, "console_unhealthy": unhealthy,
        "stopped_answering": stopped_answering,
        "req_per_s": answered / elapsed,
        "cpu_s": cpu_after - cpu_before, "answered": answered, "elapsed": elapsed,
    }


def reference_row(build, clients, seconds, total_rate=0.0):
    """The plainest libmodbus server under `clients` load processes, flat out, or asked
    `total_rate` requests a second together."""
    port = distinct_port()
    server = subprocess.Popen([os.path.join(build, "bench", "bench_reference_server"), str(port)],
                              stdout=subprocess.DEVNULL)
    time.sleep(0.3)
    try:
        cpu_before = cpu_seconds(server.pid)
        answered, _, errors = flood(os.path.join(build, "bench", "bench_modbus_load"), port,
                                    clients, seconds, total_rate / clients)
        cpu = cpu_seconds(server.pid) - cpu_before
    finally:
        stop(server)
    return {"req_per_s": answered / seconds, "cpu_us": cpu * 1e6 / max(answered, 1),
            "errors": errors}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--clients", default="0,1,4,8,32,64")
    parser.add_argument("--quick", action="store_true", help="one round of 3 s windows")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--tiltgate")
    args = parser.parse_args()
    if args.quick:
        args.rounds, args.seconds = 1, 3.0
    binary = args.tiltgate or os.path.join(args.build, "tiltgate")
    counts = [int(c) for c in args.clients.split(",")]
    folder = tempfile.mkdtemp(prefix="tiltgate-flood-")
    rows = {c: [] for c in counts}
    references = {c: [] for c in counts if c}
    paced = {c: [] for c in counts if c}
    try:
        for _ in range(args.rounds):
            for clients in counts:
                row = gateway_row(binary, args.build, folder, clients, args.seconds)
                rows[clients].append(row)
                if clients:
                    references[clients].append(reference_row(args.build, clients, args.seconds))
                    paced[clients].append(
                        reference_row(args.build, clients, args.seconds, row["req_per_s"]))
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    report(rows, references, paced, args)


def report(rows, references, paced, args):
    med = lambda rs, k: statistics.median(r[k] for r in rs)
    idle = rows.get(0)
    idle_polls = med(idle, "polls_per_s") if idle else None
    idle_cpu_rate = statistics.median(r["cpu_s"] / r["elapsed"] for r in idle) if idle else 0.0
    print(f"A line of {SENSORS} H6 at {BAUD} baud, poll_ms = {POLL_MS}, {CONSOLE_SESSIONS} console "
          f"sessions reading /api/sensors every {CONSOLE_PERIOD_S * 1000:.0f} ms, MQTT and "
          f"Sparkplug on; {args.rounds} round(s) of {args.seconds:g} s ({os.cpu_count()} cores)")
    print("| Modbus clients | bus polls/s | against idle | longest reply in the window (ms) | "
          "longest since start (ms) | waits held by the machine | given up (overloaded) | exception answers | console reads showing a sensor "
          "down | 'stopped answering' | Modbus req/s | libmodbus req/s | CPU us/req gateway / "
          "libmodbus | gateway/libmodbus | net of idle / libmodbus | libmodbus at the gateway's req/s: "
          "CPU us/req | net of idle / it |")
    print("| ---: " * 17 + "|")
    for clients, rs in rows.items():
        polls = med(rs, "polls_per_s")
        line = (f"| {clients} | {polls:.1f} | "
                f"{polls / idle_polls:.3f} | " if idle_polls else f"| {clients} | {polls:.1f} | - | ")
        bounds = [r["window_bound_ms"] for r in rs if r["window_bound_ms"] is not None]
        line += f"<= {max(bounds):g} | " if bounds else "- | "
        line += (f"{max(r['slowest_ms'] for r in rs):.0f} | {med(rs, 'held'):.0f} | "
                 f"{med(rs, 'overloaded'):.0f} | {sum(r['exceptions'] for r in rs)} | "
                 f"{sum(r['console_unhealthy'] for r in rs)} of {sum(r['console_reads'] for r in rs)} | "
                 f"{sum(r['stopped_answering'] for r in rs)} |")
        if clients:
            ref = references[clients]
            cpu = [r["cpu_s"] * 1e6 / max(r["answered"], 1) for r in rs]
            net = [(r["cpu_s"] - idle_cpu_rate * r["elapsed"]) * 1e6 / max(r["answered"], 1)
                   for r in rs]
            same = paced[clients]
            ratio = statistics.median(c / q["cpu_us"] for c, q in zip(cpu, ref))
            net_ratio = statistics.median(n / q["cpu_us"] for n, q in zip(net, ref))
            same_ratio = statistics.median(n / q["cpu_us"] for n, q in zip(net, same))
            line += (f" {med(rs, 'req_per_s'):.0f} | {med(ref, 'req_per_s'):.0f} | "
                     f"{statistics.median(cpu):.1f} / {med(ref, 'cpu_us'):.1f} | {ratio:.2f} | "
                     f"{net_ratio:.2f} | {med(same, 'cpu_us'):.1f} | {same_ratio:.2f} |")
        else:
            line += (f" - | - | gateway idle: {idle_cpu_rate * 100:.1f} % of a core | - | - | - "
                     "| - |")
        print(line, flush=True)
    errors = sum(r["errors"] for rs in rows.values() for r in rs)
    if errors:
        print(f"\n{errors} load process(es) reported errors (a closed connection, a wrong reply)")


if __name__ == "__main__":
    main()
