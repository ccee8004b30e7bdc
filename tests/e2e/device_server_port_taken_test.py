#!/usr/bin/env python3
"""A commissioning command on a device server's port that a running gateway holds (issue 54,
defect 2; docs/operations.md, "Serial device servers"): Debian's ser2net serves a simulated
Rieker H6 over RFC 2217, build/tiltgate run holds its one connection, without a control socket,
and `tiltgate info --port rfc2217://HOST:PORT` makes a connection of its own, which ser2net turns
away. The command says so (the device server closed the connection, the port is probably
held, what to do) and exits 1; it does not blame the baud rate or the wiring.

Usage: /usr/bin/python3 device_server_port_taken_test.py path/to/tiltgate
"""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import Simulator  # noqa: E402
from ser2net_server import Ser2net  # noqa: E402
from spb_e2e import processes  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402

CONFIG = """[server]
listen = "127.0.0.1"
port = %(modbus)d
control_socket = ""
state_dir = "%(dir)s/state"

[[bus]]
name = "line1"
port = "%(url)s"
protocol = "rieker"
baud = 125000

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
unit_id = 1
"""


def scenario(t):
    tiltgate, _ = arguments()
    if not shutil.which("ser2net"):
        t.check("ser2net is installed (Debian package ser2net; run scripts/setup)", False)
        return
    sim = Simulator(tiltgate, t.dir, "rieker", "h6:223", baud=125000, name="rieker")
    server = Ser2net(t.dir, sim.link, 125000, "rfc2217", name="ser2net")
    server.start()
    t.logs.append(("simulator", sim.err_path))
    t.logs.append(("ser2net", server.log_path))
    info = ["info", "--port", server.url, "--baud", "125000", "--address", "223"]

    free = subprocess.run([tiltgate, *info], capture_output=True, text=True, timeout=60)
    t.check("with the port free, info reads the H6 over RFC 2217",
            free.returncode == 0 and "9600223" in free.stdout, (free.stdout, free.stderr))

    config = os.path.join(t.dir, "gateway.toml")
    with open(config, "w") as f:
        f.write(CONFIG % {"modbus": processes.free_port(), "dir": t.dir, "url": server.url})
    log_path = os.path.join(t.dir, "gateway.log")
    t.logs.append(("gateway", log_path))
    gateway = processes.start([tiltgate, "run", "--config", config],
                              stdout=open(log_path, "w"), stderr=subprocess.STDOUT)
    t.check("the gateway connects to the device server and holds its port",
            processes.wait_until(lambda: "connected to " + server.url in
                                 open(log_path).read(), 20), processes.tail(log_path))

    held = subprocess.run([tiltgate, *info], capture_output=True, text=True, timeout=60)
    said = "stdout:\n%sstderr:\n%s" % (held.stdout, held.stderr)
    endpoint = "%s:%d" % (server.host, server.port)
    t.check("info on the held port exits 1", held.returncode == 1, said)
    t.check("  saying the device server closed the connection and the port is probably held",
            ("the device server at %s closed the connection" % endpoint) in said and
            "the port is probably held by a running gateway or another client; stop it, or run "
            "the command through the gateway's control socket" in said, said)
    t.check("  and not that the sensor gave no reply, with a baud rate and wiring hint",
            "no reply from address" not in held.stderr and "check the baud rate" not in said,
            said)
    gateway.terminate()
    gateway.wait(timeout=20)


if __name__ == "__main__":
    sys.exit(Checks("device-server-port-taken").run(scenario))
