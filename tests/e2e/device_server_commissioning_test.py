#!/usr/bin/env python3
"""The commissioning commands over a serial device server (issue 43, item 4): `tiltgate scan` and
`tiltgate info` take `--port tcp://HOST:PORT` and `--port rfc2217://HOST:PORT` as they take a tty,
against Debian's ser2net serving a simulator's pseudo-terminal.
- scan over raw TCP finds a Rieker H6 and H4360 (models and serial numbers), and the two slaves
  of a Modbus RTU line ("RTU over TCP");
- scan over RFC 2217 with `--baud 62500` finds the Rieker sensors of a line whose simulator
  answers only at 62500 while ser2net starts at 9600: scan set the rate over RFC 2217;
- info reads a sensor's serial and angles over both.

Usage: /usr/bin/python3 device_server_commissioning_test.py path/to/tiltgate
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import Simulator  # noqa: E402
from ser2net_server import Ser2net  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402


def run(tiltgate, *args):
    """A commissioning command's exit status and output (stdout then stderr)."""
    done = subprocess.run([tiltgate, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True, timeout=60)
    return done.returncode, done.stdout + done.stderr


def row(output, address, *words):
    """Whether scan's table has a row for `address` holding each of `words`."""
    for line in output.splitlines():
        fields = line.split()
        if fields and fields[0] == str(address) and all(w in fields for w in words):
            return True
    return False


def scenario(t):
    tiltgate, _ = arguments()
    if not shutil.which("ser2net"):
        t.check("ser2net is installed (Debian package ser2net; run scripts/setup)", False)
        return
    rieker = Simulator(tiltgate, t.dir, "rieker", "h6:223,h4360:224", baud=125000, name="rieker")
    rieker.command("angle 223 12.5 -3.25")
    raw = Ser2net(t.dir, rieker.link, 125000, "raw", name="ser2net-rieker")
    raw.start()
    slow = Simulator(tiltgate, t.dir, "rieker", "h6:223,h4360:224", baud=62500, name="slow")
    slow.command("angle 223 12.5 -3.25")
    rfc = Ser2net(t.dir, slow.link, 9600, "rfc2217", name="ser2net-slow")
    rfc.start()
    rtu = Simulator(tiltgate, t.dir, "modbus-rtu", "modbus-rtu:5,modbus-rtu:9", baud=19200,
                    name="rtu")
    rtu_server = Ser2net(t.dir, rtu.link, 19200, "raw", name="ser2net-rtu")
    rtu_server.start()
    for title, path in (("rieker", rieker.err_path), ("slow rieker", slow.err_path),
                        ("rtu", rtu.err_path), ("ser2net rieker", raw.log_path),
                        ("ser2net slow", rfc.log_path), ("ser2net rtu", rtu_server.log_path)):
        t.logs.append((title, path))

    status, out = run(tiltgate, "scan", "--port", raw.url, "--from", "220", "--to", "226")
    t.check("scan --port %s exits 0" % raw.url, status == 0, out)
    t.check("scan over raw TCP finds the H6 at 223 with its serial",
            row(out, 223, "h6", "9600223", "ok"), out)
    t.check("scan over raw TCP finds the H4360 at 224 with its serial",
            row(out, 224, "h4360", "9600224", "ok"), out)
    t.check("scan over raw TCP finds those two only",
            re.search(r"^2 sensor\(s\) found at 125000 baud: 223, 224;", out, re.M), out)

    status, out = run(tiltgate, "scan", "--port", rfc.url, "--baud", "62500",
                      "--from", "220", "--to", "226")
    t.check("scan --port %s --baud 62500 exits 0" % rfc.url, status == 0, out)
    t.check("scan over RFC 2217 at 62500 (ser2net starts at 9600) finds both sensors",
            row(out, 223, "h6", "9600223") and row(out, 224, "h4360", "9600224") and
            re.search(r"^2 sensor\(s\) found at 62500 baud: 223, 224;", out, re.M), out)

    status, out = run(tiltgate, "scan", "--port", rtu_server.url, "--protocol", "modbus-rtu",
                      "--from", "1", "--to", "10")
    t.check("scan --port %s --protocol modbus-rtu (RTU over TCP) exits 0" % rtu_server.url,
            status == 0, out)
    t.check("scan over raw TCP finds the RTU slaves 5 and 9",
            re.search(r"^2 sensor\(s\) found at 19200 baud: 5, 9;", out, re.M), out)

    for server, extra in ((raw, []), (rfc, ["--baud", "62500"])):
        status, out = run(tiltgate, "info", "--port", server.url, *extra, "--address", "223")
        t.check("info --port %s exits 0" % server.url, status == 0, out)
        t.check("info over %s reads the H6's serial" % server.mode,
                re.search(r"^serial:\s+9600223$", out, re.M), out)
        t.check("info over %s reads its angles" % server.mode,
                re.search(r"^angle x:\s+12\.500 deg$", out, re.M) and
                re.search(r"^angle y:\s+-3\.250 deg$", out, re.M), out)

    status, out = run(tiltgate, "info", "--port", rtu_server.url, "--protocol", "modbus-rtu",
                      "--address", "5")
    t.check("info over raw TCP reads the RTU slave's identification",
            status == 0 and re.search(r"^product:\s+TG-RTU-INC$", out, re.M), out)


if __name__ == "__main__":
    sys.exit(Checks("device-server-commissioning").run(scenario))
