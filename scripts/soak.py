#!/usr/bin/env python3
"""The soak run behind scripts/soak: build/tiltgate serving simulated sensors for MINUTES while
hostile clients, a faulty serial line and configuration reloads work on it. Python's standard
library only.

- Serial faults: the Rieker bus reaches its simulator through a relay on a second
  pseudo-terminal that flips bits and drops bytes now and then, and "unplugs" the tty (closes
  it, removes the link, brings it back) every --unplug-every seconds.
- Hostile clients: connection hoarders (40 silent connections from five addresses, more than
  max_clients), garbage senders, half-request stallers, connect/close churn.
- A PLC (127.0.0.1) reads unit 1 every 200 ms and reconnects at once when cut off: a read that
  cannot get through for 3 s is a lock-out.
- A writer sets zero_x of unit 1 every second; each write answered OK is checked against the
  simulator: the angle read afterwards must be the raw angle minus the value written (within
  the simulator's sway, +-0.25 degrees; each value is at least 2 degrees from any zero the
  sensor may hold). A write
  answered OK that the sensor did not take is a false success.
- Reloads: SIGHUP every --reload-every seconds, cycling a second valid configuration, an
  invalid one, and the first.
- Every 5 s: the gateway's RSS and open file descriptors.

Exits 0 when the gateway lived, memory and descriptors stayed flat, no write succeeded falsely
and the PLC was never locked out; prints a summary table either way.
"""
import argparse
import os
import random
import select
import signal
import socket
import statistics
import struct
import subprocess
import sys
import tempfile
import threading
import time
import tty

stop = threading.Event()
lock = threading.Lock()
counts = {}


def count(name, n=1):
    with lock:
        counts[name] = counts.get(name, 0) + n


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


# ---- Modbus TCP, just enough (bench/modbus_tcp_client.py) ------------------------------------

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench"))
from modbus_tcp_client import modbus_call, read_input  # noqa: E402


def float_of(words):
    return struct.unpack(">f", struct.pack(">HH", *words))[0]


# ---- The faulty serial line ----------------------------------------------------------------

class FaultyLine(threading.Thread):
    """Relays bytes between the gateway's tty (a pty it makes, linked at `link`) and the
    simulator's (`sim_link`), corrupting and dropping a few, and unplugging now and then."""

    def __init__(self, sim_link, link, unplug_every, flip=0.002, drop=0.002):
        super().__init__(daemon=True)
        self.sim_link, self.link = sim_link, link
        self.unplug_every, self.flip, self.drop = unplug_every, flip, drop

    def plug(self):
        master, slave = os.openpty()
        tty.setraw(slave)
        name = os.ttyname(slave)
        os.close(slave)  # the gateway opens it by name; the master keeps the pair alive
        tmp = self.link + ".new"
        os.symlink(name, tmp)
        os.replace(tmp, self.link)
        return master

    def mangle(self, data):
        out = bytearray()
        for b in data:
            r = random.random()
            if r < self.drop:
                count("line_bytes_dropped")
                continue
            if r < self.drop + self.flip:
                b ^= 1 << random.randrange(8)
                count("line_bits_flipped")
            out.append(b)
        return bytes(out)

    def run(self):
        sim = os.open(self.sim_link, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(sim)
        master = self.plug()
        next_unplug = time.monotonic() + self.unplug_every
        while not stop.is_set():
            if time.monotonic() >= next_unplug:
                os.unlink(self.link)
                os.close(master)
                count("tty_unplugs")
                stop.wait(2.0)
                master = self.plug()
                next_unplug = time.monotonic() + self.unplug_every
            ready, _, _ = select.select([sim, master], [], [], 0.1)
            for fd in ready:
                try:
                    data = os.read(fd, 4096)
                except OSError:
                    continue  # the gateway has not opened its side yet
                target = master if fd == sim else sim
                try:
                    os.write(target, self.mangle(data))
                except OSError:
                    pass


# ---- Clients -------------------------------------------------------------------------------

def connect(port, source="127.0.0.1", timeout=3.0):
    s = socket.socket()
    s.settimeout(timeout)
    s.bind((source, 0))
    s.connect(("127.0.0.1", port))
    return s


def hoarder(port):
    """Keeps 40 silent connections open from five addresses (127.0.0.2 .. 127.0.0.6): more than
    max_clients (32), and more than max_clients_per_host (8) from each."""
    held = []
    while not stop.is_set():
        held = [s for s in held if alive(s)]
        while len(held) < 40 and not stop.is_set():
            try:
                held.append(connect(port, f"127.0.0.{2 + len(held) % 5}"))
                count("hoarder_connections")
            except OSError:
                break
        stop.wait(0.5)
    for s in held:
        s.close()


def alive(s):
    try:
        s.setblocking(False)
        data = s.recv(1)
        s.setblocking(True)
        if data == b"":
            s.close()
            return False
        return True
    except BlockingIOError:
        s.setblocking(True)
        return True
    except OSError:
        s.close()
        return False


def garbage(port):
    while not stop.is_set():
        try:
            s = connect(port, "127.0.0.7", timeout=1.0)
            s.sendall(os.urandom(random.randrange(1, 300)))
            count("garbage_connections")
            try:
                while s.recv(512):
                    pass
            except OSError:
                pass
            s.close()
        except OSError:
            pass
        stop.wait(0.05)


def staller(port):
    while not stop.is_set():
        try:
            s = connect(port, "127.0.0.8", timeout=10.0)
            s.sendall(b"\x00\x01\x00\x00\x00")  # half an MBAP header, then nothing
            count("stalled_connections")
            try:
                s.recv(1)
            except OSError:
                pass
            s.close()
        except OSError:
            stop.wait(0.2)


def churner(port):
    while not stop.is_set():
        try:
            connect(port, "127.0.0.9", timeout=1.0).close()
            count("churn_connections")
        except OSError:
            stop.wait(0.05)


def plc(port):
    sock = None
    failing_since = None
    while not stop.is_set():
        try:
            if sock is None:
                sock = connect(port)
            read_input(sock, 1, 6, 2)
            count("plc_reads")
            failing_since = None
        except ValueError:
            count("plc_reads")  # an exception reply is an answer (offline while unplugged)
            failing_since = None
        except OSError:
            count("plc_reconnects")
            if sock is not None:
                sock.close()
            sock = None
            failing_since = failing_since or time.monotonic()
            if time.monotonic() - failing_since > 3.0:
                count("plc_lockouts")
                failing_since = time.monotonic()
            stop.wait(0.02)
            continue
        stop.wait(0.2)


def writer(port, raw_x):
    sock = None
    recent = [0.0]  # the zero in force, and values tried since (one may have been taken)
    while not stop.is_set():
        stop.wait(1.0)
        # At least 2 degrees from any zero the sensor may hold, well past its sway (+-0.25 deg,
        # so two readings differ by up to 0.5), so a write it did not take cannot pass for one
        # it did.
        value = 0.0
        while any(abs(value - r) < 2.0 for r in recent):
            value = round(random.uniform(-20.0, 20.0), 2)
        recent.append(value)
        words = struct.unpack(">HH", struct.pack(">f", value))
        try:
            if sock is None:
                sock = connect(port, timeout=15.0)
            reply = modbus_call(sock, 1, struct.pack(">BHHB2H", 16, 1, 2, 4, *words))
        except OSError:
            count("writes_lost_connection")
            sock = None
            continue
        if reply[0] & 0x80:
            count(f"writes_exception_{reply[1]:02X}")
            continue
        count("writes_ok")
        if verify(sock, raw_x - value):
            recent = [value]
        elif len(recent) > 8:
            recent = recent[-8:]  # keeps a free value in reach


def verify(sock, expected):
    """After a write answered OK: fresh readings must show the new zero."""
    deadline = time.monotonic() + 20.0
    try:
        first_seq = read_input(sock, 1, 15, 1)[0]
    except (OSError, ValueError):
        first_seq = None
    while time.monotonic() < deadline and not stop.is_set():
        time.sleep(0.3)
        try:
            seq = read_input(sock, 1, 15, 1)[0]
            if first_seq is not None and (seq - first_seq) % 65536 < 3:
                continue
            x = float_of(read_input(sock, 1, 0, 2))
        except (OSError, ValueError):
            continue
        if abs(x - expected) < 0.55:
            count("writes_confirmed")
            return True
        count("writes_false_success")
        print(f"FALSE SUCCESS: angle_x {x:.3f}, expected {expected:.3f}", flush=True)
        return False
    count("writes_unverified")
    return False


# ---- The gateway ---------------------------------------------------------------------------

def config_text(port, http_port, tty_a, tty_b, variant):
    # The second variant changes a sensor (its poll), adds one and reopens a bus (its timeout).
    poll = {"first": 100, "second": 200}[variant]
    timeout = {"first": 50, "second": 60}[variant]
    extra = "" if variant == "first" else """
[[sensor]]
name = "spare"
bus = "line-b"
model = "h6"
address = 6
unit_id = 3
"""
    return f"""
[server]
listen = "127.0.0.1"
port = {port}
writes = true
idle_timeout_ms = 10000
request_timeout_ms = 2000
control_socket = ""

[http]
port = {http_port}

[[bus]]
name = "line-a"
port = "{tty_a}"
protocol = "rieker"
reopen_max_ms = 2000

[[bus]]
name = "line-b"
port = "{tty_b}"
protocol = "rieker"
timeout_ms = {timeout}

[[sensor]]
name = "boom"
bus = "line-a"
model = "h6"
address = 223
unit_id = 1
poll_ms = {poll}

[[sensor]]
name = "mast"
bus = "line-b"
model = "h4360"
address = 101
unit_id = 2
{extra}"""


def sample(pid):
    rss = 0
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                rss = int(line.split()[1])
    return rss, len(os.listdir(f"/proc/{pid}/fd"))


def wait_for_sim(link):
    for _ in range(100):
        if os.path.exists(link):
            return
        time.sleep(0.05)
    sys.exit(f"simulator did not make {link}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--minutes", type=float, required=True)
    parser.add_argument("--tiltgate", default="build/tiltgate")
    parser.add_argument("--reload-every", type=float, default=20.0)
    parser.add_argument("--unplug-every", type=float, default=30.0)
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="tiltgate-soak-")
    procs = []
    sim_a, tty_a, tty_b = f"{work}/sim-a", f"{work}/tty-a", f"{work}/tty-b"
    procs.append(subprocess.Popen([args.tiltgate, "sim", "rieker", "--sensors", "h6:223",
                                   "--link", sim_a], stderr=subprocess.DEVNULL))
    procs.append(subprocess.Popen([args.tiltgate, "sim", "rieker", "--sensors",
                                   "h4360:101,h6:6", "--link", tty_b],
                                  stderr=subprocess.DEVNULL))
    wait_for_sim(sim_a)
    wait_for_sim(tty_b)
    FaultyLine(sim_a, tty_a, args.unplug_every).start()
    wait_for_sim(tty_a)

    port, http_port = free_port(), free_port()
    config = f"{work}/soak.toml"
    variants = {v: config_text(port, http_port, tty_a, tty_b, v) for v in ("first", "second")}
    variants["invalid"] = variants["second"] + "\n[server.nonsense]\n"
    with open(config, "w") as f:
        f.write(variants["first"])
    log = open(f"{work}/gateway.log", "w")
    gateway = subprocess.Popen([args.tiltgate, "run", "--config", config], stderr=log)
    procs.append(gateway)

    # The raw angle: the sensor's reading before anything is written (its zero is 0).
    raw_x = None
    for _ in range(100):
        try:
            with connect(port) as s:
                raw_x = float_of(read_input(s, 1, 0, 2))
                break
        except (OSError, ValueError):
            time.sleep(0.1)
    if raw_x is None:
        sys.exit("the gateway never served unit 1's angle")
    time.sleep(1.0)
    baseline = sample(gateway.pid)

    threads = [threading.Thread(target=f, args=a, daemon=True) for f, a in (
        (hoarder, (port,)), (garbage, (port,)), (staller, (port,)), (churner, (port,)),
        (plc, (port,)), (writer, (port, raw_x)))]
    for t in threads:
        t.start()

    samples = []
    start = time.monotonic()
    end = start + args.minutes * 60
    next_reload = start + args.reload_every
    cycle = ["second", "invalid", "first"]
    reloads = 0
    while time.monotonic() < end and gateway.poll() is None:
        time.sleep(5.0)
        if gateway.poll() is not None:
            break
        samples.append((time.monotonic() - start,) + sample(gateway.pid))
        if time.monotonic() >= next_reload:
            with open(config, "w") as f:
                f.write(variants[cycle[reloads % 3]])
            gateway.send_signal(signal.SIGHUP)
            reloads += 1
            next_reload += args.reload_every

    stop.set()
    for t in threads:
        t.join(timeout=20)
    alive_at_end = gateway.poll() is None
    time.sleep(3.0)  # closed connections reach the gateway
    after = sample(gateway.pid) if alive_at_end else (0, 0)
    if alive_at_end:
        gateway.send_signal(signal.SIGTERM)
        gateway.wait(timeout=20)
    for p in procs:
        if p.poll() is None:
            p.terminate()
    log.close()
    with open(f"{work}/gateway.log") as f:
        text = f.read()
    applied = text.count("configuration reloaded from")
    refused = text.count("reload refused")

    rss = [s[1] for s in samples]
    quarter = max(1, len(rss) // 4)
    early = statistics.median(rss[quarter:2 * quarter] or rss) if rss else 0
    late = statistics.median(rss[-quarter:]) if rss else 0
    problems = []
    if not alive_at_end:
        problems.append(f"the gateway died (exit {gateway.returncode})")
    if late > early * 1.10 and late - early > 2048:
        problems.append(f"memory grew: median RSS {early} kB -> {late} kB")
    if alive_at_end and after[1] > baseline[1] + 2:
        problems.append(f"descriptors grew: {baseline[1]} -> {after[1]} with the clients gone")
    if counts.get("writes_false_success", 0):
        problems.append("a write was answered OK that the sensor did not take")
    if counts.get("plc_lockouts", 0):
        problems.append("the PLC was locked out")
    if reloads >= 3 and (refused == 0 or applied == 0):
        problems.append("reloads were not all reported applied or refused")

    print(f"\nsoak: {args.minutes:g} min, log and configs in {work}")
    print(f"{'measure':<34} {'value':>14}")
    rows = [
        ("RSS at start / median early / late (kB)", f"{baseline[0]} / {early} / {late}"),
        ("RSS max (kB)", max(rss) if rss else 0),
        ("fds at start / max / after clients left", f"{baseline[1]} / {max((s[2] for s in samples), default=0)} / {after[1]}"),
        ("reloads sent / applied / refused", f"{reloads} / {applied} / {refused}"),
    ] + sorted(counts.items())
    for name, value in rows:
        print(f"{name:<34} {str(value):>14}")
    if problems:
        print("\nFAILED: " + "; ".join(problems))
        return 1
    print("\nOK: flat memory and descriptors, no false write success, the PLC always got in")
    return 0


if __name__ == "__main__":
    sys.exit(main())
