#!/usr/bin/env python3
"""The three front ends of the commissioning engine agree (issue 53; docs/commissioning.md,
"With the gateway running"; docs/web-console.md, "The API"). On one simulated bus, first with
the tty free and then with build/tiltgate serving it:
  (a) `tiltgate scan|raw|info --port TTY` on the tty alone,
  (b) the same command with `--via-gateway --control-socket PATH` (the gateway runs the engine
      and streams its events back; the command renders them as (a) does),
  (c) the web console's POST /api/buses/NAME/scan (then GET until done) and /raw.
They must find the same sensors, print the same table and --config-out file, send and receive
the same bytes, decode the same serial and show the same sensor block; a raw Set Filter through
(b) and (c) is one audit record each, under its own door and who, and none under the other's.

Two buses, one after the other, each with a gateway of its own: Rieker (H4360 and two H6, two
of them configured) and Spectron Modbus-ASCII (two Dynas).

Usage: /usr/bin/python3 commissioning_front_ends_test.py path/to/tiltgate
"""
import os
import pwd
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402  (spb_e2e on the import path)
from console_api_test import Client, start_gateway  # noqa: E402
from network_plant import Simulator  # noqa: E402
from spb_e2e import processes  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402

ADMIN, PASSWORD = "bob", "admin-pass-22"

# Each bus at 9600 baud, whose probe time-out (the wire time of a probe and its reply, and more:
# docs/commissioning.md, "`tiltgate scan`: finding the sensors on a bus") leaves a simulator on a
# busy machine time to answer; the console's scan takes no --probe-timeout-ms to give it more.
# Each bus: the simulator's family, --protocol and sensors; the bus's protocol and options; the
# scanned range; the sensors the gateway's configuration names (model, address); a raw read of
# the serial or revision (function, the line of the decoded reply to compare), and whether the
# family has a Set Filter to send raw.
BUSES = [
    {"name": "rieker", "family": "rieker", "sim_protocol": None,
     "sensors": "h4360:101,h6:103,h6:105", "protocol": "rieker", "options": ["--baud", "9600"],
     "range": (100, 106), "configured": [("h4360", 101), ("h6", 103)],
     "read": (103, "37", "serial:"), "set_filter": True},
    {"name": "spectron", "family": "spectron", "sim_protocol": "modbus",
     "sensors": "dyna:7,dyna:9", "protocol": "spectron-modbus", "options": ["--baud", "9600"],
     "range": (6, 10), "configured": [("dyna", 7), ("dyna", 9)],
     "read": (7, "0x6A", "revision:"), "set_filter": False},
]

GATEWAY = """[server]
listen = "127.0.0.1"
port = %(modbus)d
control_socket = "%(socket)s"
state_dir = "%(dir)s/state-%(name)s"

[http]
listen = "127.0.0.1"
port = %(http)d
users_file = "%(users)s"

[[bus]]
name = "line1"
port = "%(tty)s"
protocol = "%(protocol)s"
%(bus_keys)s
"""

SENSOR = """
[[sensor]]
name = "s%(address)d"
bus = "line1"
model = "%(model)s"
address = %(address)d
unit_id = %(unit)d
"""


def run(tiltgate, argv):
    """A tiltgate command; its exit status, stdout and stderr."""
    done = subprocess.run([tiltgate] + argv, capture_output=True, text=True, timeout=60)
    return done.returncode, done.stdout, done.stderr


def scan_rows(stdout):
    """The scan table's rows as (address, model, serial, firmware): the address the row's first
    word, the others cut at their headers' columns (a firmware such as "Rev A.8" holds a space;
    the BAUD column is aligned right)."""
    lines = stdout.splitlines()
    header = next((i for i, line in enumerate(lines) if line.startswith("ADDRESS")), None)
    if header is None:
        return []
    starts = [lines[header].index(name) for name in ("MODEL", "SERIAL", "FIRMWARE", "LOCK")]
    rows = []
    for line in lines[header + 1:]:
        if not re.match(r"\d+ +\d+ ", line):  # the summary's "2 sensor(s) found ..." ends it
            break
        model, serial, firmware = (line[s:e].strip() for s, e in zip(starts, starts[1:]))
        rows.append((int(line.split()[0]), model, serial, firmware))
    return rows


def scan_text(stdout):
    """A scan's stdout without what differs by run: its duration and the file it wrote."""
    return [re.sub(r" in [0-9.]+ s$", " in T s", line) for line in stdout.splitlines()
            if not line.startswith("wrote ")]


def field(text, label):
    """The rest of the first line of `text` that starts with `label` ("sent:"); None if none."""
    for line in (text or "").splitlines():
        if line.startswith(label):
            return line[len(label):].strip()
    return None


def exchange(stdout_or_reply):
    """(sent, received) hex of a raw exchange: from the command's lines (the verdict after the
    received bytes cut off) or from the console's reply."""
    if isinstance(stdout_or_reply, dict):
        return stdout_or_reply.get("sent"), stdout_or_reply.get("received")
    received = field(stdout_or_reply, "received:")
    return field(stdout_or_reply, "sent:"), received and received.split("  (")[0]


def identity_blocks(stdout):
    """`info`'s sensor blocks without the angle lines, which move between polls."""
    moving = ("angle x:", "angle y:", "tilt:")
    return [line for line in stdout.splitlines() if not line.startswith(moving)]


def console_scan(client, low, high):
    status, body = client.request("POST", "/api/buses/line1/scan", {"from": low, "to": high})
    if status != 202:
        return None, (status, body)
    processes.wait_until(
        lambda: not client.request("GET", "/api/buses/line1/scan")[1].get("running", True), 40)
    return client.request("GET", "/api/buses/line1/scan")[1], None


def change_records(client, door):
    """The audit records under `door` of a raw frame that may change a sensor."""
    status, body = client.request("GET", "/api/audit?door=" + door.replace(" ", "%20"))
    records = body.get("records", []) if status == 200 and isinstance(body, dict) else []
    return [r for r in records if r.get("setting", "").startswith("function")]


class FrontEnds:
    """One simulated bus of BUSES: the commands of (a) run at once on its free tty; serve()
    starts a gateway on it, for (b) and (c); then the checks, each comparing what all ran."""

    def __init__(self, t, tiltgate, bus):
        self.t, self.tiltgate, self.bus, self.name = t, tiltgate, bus, bus["name"]
        sim = Simulator(tiltgate, t.dir, bus["family"], bus["sensors"],
                        protocol=bus["sim_protocol"], name="sim-" + self.name)
        t.logs.append(("%s simulator" % self.name, sim.err_path))
        self.tty = sim.link
        self.line = ["--port", sim.link, "--protocol", bus["protocol"]] + bus["options"]
        low, high = bus["range"]
        self.scan = ["scan"] + self.line + ["--from", str(low), "--to", str(high), "--config-out"]
        self.address, function, self.decoded_label = bus["read"]
        self.function = int(function, 0)
        self.read = ["raw"] + self.line + ["--address", str(self.address), "--function", function]
        self.addresses = [int(sensor.split(":")[1]) for sensor in bus["sensors"].split(",")]
        self.info = ["info"] + self.line + [
            "--address", ",".join(str(a) for a in self.addresses)]
        # (a): the tty is the command's own.
        self.alone_out = self.path("alone.toml")
        self.alone_scan = run(tiltgate, self.scan + [self.alone_out])
        self.alone_rows = scan_rows(self.alone_scan[1])
        t.check("%s: (a) scan finds every simulated sensor" % self.name,
                self.alone_scan[0] == 0 and
                [row[0] for row in self.alone_rows] == sorted(self.addresses), self.alone_scan)
        self.alone_read = run(tiltgate, self.read)
        t.check("%s: (a) raw read answered" % self.name, self.alone_read[0] == 0 and
                field(self.alone_read[1], self.decoded_label), self.alone_read)
        self.alone_info = run(tiltgate, self.info)

    def path(self, what):
        return os.path.join(self.t.dir, "%s-%s" % (self.name, what))

    def serve(self, users):
        """A gateway on the tty with its control socket and console; logs in to the console."""
        socket_path = self.path("control.sock")
        http_port = processes.free_port()
        keys = {"modbus": processes.free_port(), "socket": socket_path, "dir": self.t.dir,
                "name": self.name, "http": http_port, "users": users, "tty": self.tty,
                "protocol": self.bus["protocol"],
                "bus_keys": "baud = %s" % self.bus["options"][1] if self.bus["options"] else ""}
        text = GATEWAY % keys
        for unit, (model, at) in enumerate(self.bus["configured"], start=1):
            text += SENSOR % {"address": at, "model": model, "unit": unit}
        config, log_path = self.path("gateway.toml"), self.path("gateway.log")
        with open(config, "w") as f:
            f.write(text)
        self.t.logs.append(("%s gateway" % self.name, log_path))
        self.gateway = start_gateway(self.tiltgate, config, log_path, http_port)
        processes.wait_until(lambda: os.path.exists(socket_path), 10)
        self.via = ["--via-gateway", "--control-socket", socket_path]
        self.console = Client(http_port)
        self.console.login(ADMIN, PASSWORD)

    def stop(self):
        self.gateway.terminate()
        self.gateway.wait(timeout=20)

    def compare_scans(self):
        """1. The same sensors, table and --config-out file."""
        t, name = self.t, self.name
        socket_out = self.path("socket.toml")
        socket_scan = run(self.tiltgate, self.scan + [socket_out] + self.via)
        t.check("%s: (b) goes through the gateway" % name,
                "through the running gateway" in socket_scan[2], socket_scan)
        t.check("%s: (a) and (b) print the same table on stdout" % name,
                scan_text(self.alone_scan[1]) == scan_text(socket_scan[1]) and
                socket_scan[0] == self.alone_scan[0], (self.alone_scan, socket_scan))
        t.check("%s: (a) and (b) find the same sensors" % name,
                self.alone_rows == scan_rows(socket_scan[1]), (self.alone_rows, socket_scan[1]))
        with open(self.alone_out) as a, open(socket_out) as b:
            alone_file, socket_file = a.read(), b.read()
        t.check("%s: (b)'s --config-out file equals (a)'s" % name, alone_file == socket_file,
                (alone_file, socket_file))
        state, error = console_scan(self.console, *self.bus["range"])
        state = state or {}
        found = [(s["address"], s["model"], s["serial"], s["firmware"])
                 for s in state.get("found", [])]
        t.check("%s: (c) finds the same sensors (address, model, serial, firmware)" % name,
                found == self.alone_rows and not state.get("error"), error or state)
        t.check("%s: (c)'s table is (a)'s" % name,
                scan_text(state.get("output", "")) == scan_text(self.alone_scan[1]),
                (state, self.alone_scan[1]))
        t.check("%s: (c)'s [[sensor]] tables are those of (a)'s --config-out file" % name,
                found and all(s["config"] in alone_file for s in state["found"]),
                (state, alone_file))

    def compare_reads(self):
        """2. One raw read: the same bytes each way and the same decoded answer."""
        t, name, label = self.t, self.name, self.decoded_label
        alone = self.alone_read
        socket = run(self.tiltgate, self.read + self.via)
        status, console = self.console.request(
            "POST", "/api/buses/line1/raw", {"address": self.address, "function": self.function})
        sent, received = exchange(alone[1])
        t.check("%s: (a), (b) and (c) send the same request bytes" % name,
                sent and sent == exchange(socket[1])[0] == exchange(console)[0],
                (alone, socket, console))
        t.check("%s: and receive the same reply bytes" % name,
                received and received == exchange(socket[1])[1] == exchange(console)[1],
                (alone, socket, console))
        decoded = field(alone[1], label)
        t.check("%s: and decode the same %s" % (name, label.rstrip(":")),
                decoded and decoded == field(socket[1], label) ==
                field(console.get("decoded") if status == 200 else "", label),
                (alone, socket, console))
        t.check("%s: (a) and (b) print the same exchange" % name, alone[:2] == socket[:2],
                (alone, socket))

    def compare_set_filter_records(self):
        """2. A raw Set Filter (the locked sensor refuses it: NAK 4) from each door in the
        gateway is one record under that door, who its caller, and none under the other."""
        t, name = self.t, self.name
        unix_user = "user %s (uid %d," % (pwd.getpwuid(os.getuid()).pw_name, os.getuid())
        run(self.tiltgate, ["raw"] + self.line + ["--address", str(self.address),
                                                  "--function", "41", "--data", "02"] + self.via)
        self.console.request("POST", "/api/buses/line1/raw",
                             {"address": self.address, "function": 41, "data": "02"})
        wanted = ("line1/s%d" % self.address, "function 41 (set filter response)", "02",
                  "nak 0x04")
        socket_records = change_records(self.console, "control socket")
        t.check("%s: (b)'s Set Filter is one record under the control socket, its Unix user's"
                % name, [(r["who"].startswith(unix_user), r["sensor"], r["setting"], r["new"],
                          r["result"]) for r in socket_records] == [(True,) + wanted],
                socket_records)
        console_records = change_records(self.console, "console")
        t.check("%s: (c)'s Set Filter is one record under the console, its user's" % name,
                [(r["who"], r["sensor"], r["setting"], r["new"], r["result"])
                 for r in console_records] == [(ADMIN,) + wanted], console_records)

    def compare_info(self):
        """3. info: the same sensor blocks, angles aside."""
        socket = run(self.tiltgate, self.info + self.via)
        self.t.check("%s: (a) and (b) print the same sensor blocks, angles aside" % self.name,
                     self.alone_info[0] == socket[0] == 0 and "serial:" in socket[1] and
                     identity_blocks(self.alone_info[1]) == identity_blocks(socket[1]),
                     (self.alone_info, socket))


def scenario(t):
    tiltgate, _ = arguments()
    users = os.path.join(t.dir, "users")
    subprocess.run([tiltgate, "user", "add", ADMIN, "--role", "admin", "--users-file", users],
                   input=PASSWORD + "\n", text=True, check=True, capture_output=True, timeout=30)
    for bus in BUSES:
        front_ends = FrontEnds(t, tiltgate, bus)
        front_ends.serve(users)
        front_ends.compare_scans()
        front_ends.compare_reads()
        if bus["set_filter"]:
            front_ends.compare_set_filter_records()
        front_ends.compare_info()
        front_ends.stop()


if __name__ == "__main__":
    sys.exit(Checks("commissioning-front-ends").run(scenario))
