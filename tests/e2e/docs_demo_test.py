#!/usr/bin/env python3
"""What the README and docs/default-maps.md say a new user finds, against `tiltgate demo`
itself and a plain Modbus TCP client (issue 54, item 8):

- docs/default-maps.md is the register maps `tiltgate demo --map` prints, unit for unit (the
  headings without the demo's port): the same sensors at the same unit ids, the Modbus RTU
  inclinometer's table included;
- the units the page states hold for what each unit serves: angle_x and angle_y in degrees
  (float32) are the same angles as angle_x_cdeg and angle_y_cdeg in 0.01 degree (int16), read
  in one request, and model_code is the code the page gives for the heading's model;
- the README's "What a PLC reads": input registers, discrete inputs and holding registers are
  served over exactly the ranges it names (each range answers in one read, the next register
  is exception 02) on every unit of the demo;
- the README's table of commands has a row for each command `tiltgate --help` lists;
- the README's table of supported devices lists every `[[bus]] protocol` the gateway takes
  (as `tiltgate scan --help` lists them), Modbus TCP devices included.

Usage: /usr/bin/python3 docs_demo_test.py path/to/tiltgate
"""
import os
import re
import socket
import struct
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: E402,F401  (spb_e2e on the import path)
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e import processes  # noqa: E402

# Modbus function codes by table, and their names in the README.
READS = {"coil": 1, "discrete": 2, "holding": 3, "input": 4}
README_TABLES = {"input registers": "input", "discrete inputs": "discrete",
                 "holding registers": "holding"}
MODELS = {"h6": "H6", "h4360": "H4360", "dyna": "Dyna", "modbus-rtu": "Modbus RTU device",
          "modbus-tcp": "Modbus TCP device"}


class ModbusClient:
    """One Modbus TCP connection; read() is ("ok", data bytes) or ("exception", code)."""

    def __init__(self, port):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=10)
        self.transaction = 0

    def read(self, unit, table, address, count):
        self.transaction += 1
        pdu = struct.pack(">BHH", READS[table], address, count)
        self.sock.sendall(struct.pack(">HHHB", self.transaction, 0, len(pdu) + 1, unit) + pdu)
        header = self._exactly(7)
        _, _, length, _ = struct.unpack(">HHHB", header)
        body = self._exactly(length - 1)
        if body[0] & 0x80:
            return "exception", body[1]
        return "ok", body[2:]

    def _exactly(self, n):
        data = b""
        while len(data) < n:
            chunk = self.sock.recv(n - len(data))
            if not chunk:
                raise RuntimeError("the gateway closed the connection")
            data += chunk
        return data


def tables_of(markdown):
    """{unit id: (heading, [rows as dicts])} of a page of `tiltgate map --format markdown`."""
    units, unit, columns = {}, None, []
    for line in markdown.split("\n"):
        heading = re.match(r"### (Unit (\d+): \S+ \(([^)]+)\))", line)
        if heading:
            unit = int(heading.group(2))
            units[unit] = (heading.group(1), heading.group(3), [])
            columns = []
        elif line.startswith("| table |"):
            columns = [c.strip() for c in line.strip("|").split("|")]
        elif line.startswith("| ") and columns and not line.startswith("| ---"):
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
            units[unit][2].append(dict(zip(columns, cells)))
    return units


def scenario(t):
    tiltgate, source = arguments()
    page = open(os.path.join(source, "docs", "default-maps.md"), encoding="utf-8").read()
    readme = open(os.path.join(source, "README.md"), encoding="utf-8").read()

    # The README's table of supported devices against the protocols the gateway takes.
    scan_help = subprocess.run([tiltgate, "scan", "--help"], capture_output=True, text=True)
    offered = re.search(r"--protocol TEXT\s+(.*?) \(default", scan_help.stdout)
    taken = set(re.findall(r"[a-z0-9-]+", offered.group(1))) if offered else set()
    table = readme[readme.find("| family | models |"):readme.find("\n\n", readme.find("| family |"))]
    listed = set(re.findall(r"^\|[^|]*\|[^|]*\| `([a-z0-9-]+)` \|", table, re.M))
    t.check("the README's table of supported devices lists every [[bus]] protocol the gateway "
            "takes (%s)" % ", ".join(sorted(taken)),
            len(taken) >= 4 and listed == taken, (sorted(listed), sorted(taken)))

    # The README's table of commands against the gateway's own list of them.
    top_help = subprocess.run([tiltgate, "--help"], capture_output=True, text=True).stdout
    commands = set(re.findall(r"^  ([a-z]+) {2,}\S", top_help.split("Subcommands:")[-1], re.M))
    described = set(re.findall(r"^\| `tiltgate ([a-z]+)", readme, re.M))
    t.check("the README's table of commands has a row for every command of `tiltgate --help` "
            "(%s)" % ", ".join(sorted(commands)),
            len(commands) >= 10 and commands <= described, sorted(commands - described))

    port = processes.free_port()
    out_path = os.path.join(t.dir, "demo.out")
    err_path = os.path.join(t.dir, "demo.err")
    t.logs.append(("demo's stderr", err_path))
    processes.start([tiltgate, "demo", "--port", str(port), "--http-port", "0", "--map",
                     "--control-socket", os.path.join(t.dir, "control.sock")],
                    stdout=open(out_path, "w"), stderr=open(err_path, "w"))
    printed = lambda: open(out_path).read() if os.path.exists(out_path) else ""
    t.check("the demo starts and prints its maps", processes.wait_until(
        lambda: "Ctrl-C stops." in printed(), 30), processes.tail(err_path))
    maps = printed().split("tiltgate demo:")[0]
    maps = re.sub(r", port %d$" % port, "", maps, flags=re.M)
    t.check("docs/default-maps.md is the register maps `tiltgate demo --map` prints, unit for "
            "unit", maps == page,
            ([l for l in page.split("\n") if l.startswith("###")],
             [l for l in maps.split("\n") if l.startswith("###")]))

    client = ModbusClient(port)
    units = tables_of(page)
    t.check("the page has a table for each of the demo's 5 units, the Modbus RTU device's too",
            sorted(units) == [1, 2, 3, 4, 5] and units[5][1] == "modbus-rtu", sorted(units))
    for unit, (heading, model, rows) in sorted(units.items()):
        by_name = {row["name"]: row for row in rows}
        stated = [(by_name.get(n, {}).get("units"), by_name.get(n, {}).get("type"))
                  for n in ("angle_x", "angle_y", "angle_x_cdeg", "angle_y_cdeg")]
        t.check("%s: the page states the angles in deg (float32) and 0.01 deg (int16)" % heading,
                stated == [("deg", "float32")] * 2 + [("0.01 deg", "int16")] * 2, stated)
        # Online first: a sensor's angles answer 0x0B until its first reading.
        online = processes.wait_until(
            lambda: client.read(unit, "discrete", 0, 1) == ("ok", b"\x01"), 20)
        t.check("%s: online" % heading, online)
        kind, data = client.read(unit, "input", 0, 6)
        if not t.check("%s: input registers 0..5 answer in one read" % heading, kind == "ok",
                       (kind, data)):
            continue
        x, y = struct.unpack(">ff", data[:8])
        x_cdeg, y_cdeg = struct.unpack(">hh", data[8:12])
        same = abs(x * 100 - x_cdeg) <= 1 and (
            (y != y and y_cdeg == -32768) or abs(y * 100 - y_cdeg) <= 1)
        t.check("%s: angle_x_cdeg and angle_y_cdeg are angle_x and angle_y in 0.01 degree "
                "(-32768 where the model has no Y axis)" % heading, same, (x, y, x_cdeg, y_cdeg))
        codes = dict(re.findall(r"(\d+) ([A-Za-z0-9 ]+?)(?:,|$)", by_name["model_code"]["description"]))
        kind, data = client.read(unit, "input", 37, 1)
        served = struct.unpack(">H", data)[0] if kind == "ok" else None
        t.check("%s: model_code is the page's code for %s" % (heading, MODELS[model]),
                codes.get(str(served)) == MODELS[model], (served, codes))

    # The README's ranges of the common block, on every unit.
    said = re.search(r"### What a PLC reads\n\n(.*?)\n\n", readme, re.S)
    ranges = [(README_TABLES[m.group(1)], int(m.group(2)), int(m.group(3))) for m in re.finditer(
        r"(input registers|discrete inputs|holding registers) (\d+)\.\.(\d+)",
        " ".join(said.group(1).split()) if said else "")]
    t.check("the README names the ranges of the three tables a PLC reads",
            sorted(r[0] for r in ranges) == ["discrete", "holding", "input"], ranges)
    for unit in sorted(units):
        for table, first, last in ranges:
            whole = client.read(unit, table, first, last - first + 1)
            past = client.read(unit, table, last + 1, 1)
            t.check("unit %d: %s %d..%d answer in one read, %d is exception 02, as the README "
                    "says" % (unit, table, first, last, last + 1),
                    whole[0] == "ok" and past == ("exception", 2), (whole, past))


if __name__ == "__main__":
    sys.exit(Checks("docs-demo").run(scenario))
