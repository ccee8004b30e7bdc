"""`tiltgate run` with the web console on one simulated Rieker H6 ("boom" at 223 on bus "line1",
Modbus and HTTP on loopback, no control socket), for the end-to-end tests that talk HTTP to the
console: an account made by `tiltgate user add`, the configuration written again with other
[http] keys or another sensor name and reloaded by SIGHUP as a test needs."""
import http.client
import json
import os
import subprocess

import spb_path  # noqa: F401
from spb_e2e import processes  # noqa: E402
from spb_e2e.plant import Simulator  # noqa: E402

CONFIG = """[server]
listen = "127.0.0.1"
port = %(modbus)d
control_socket = ""
state_dir = "%(dir)s/state"

[http]
listen = "127.0.0.1"
port = %(http)d
users_file = "%(users)s"
%(http_keys)s

[[bus]]
name = "line1"
port = "%(tty)s"
protocol = "rieker"

[[sensor]]
name = %(sensor)s
bus = "line1"
model = "h6"
address = 223
unit_id = 1
"""


class ConsoleGateway:
    """The simulator and the gateway's files in the test's folder; start() runs the gateway."""

    def __init__(self, t, tiltgate, admin):
        """`admin`: the name of an admin account (password "admin-pass-22") in its users file."""
        self.tiltgate = tiltgate
        users = os.path.join(t.dir, "users")
        subprocess.run([tiltgate, "user", "add", admin, "--role", "admin", "--users-file", users],
                       input="admin-pass-22\n", text=True, check=True, capture_output=True,
                       timeout=30)
        self.sim = Simulator(tiltgate, t.dir)
        self.modbus_port = processes.free_port()
        self.http_port = processes.free_port()
        self._keys = {"modbus": self.modbus_port, "http": self.http_port, "dir": t.dir,
                      "users": users, "tty": self.sim.link}
        self.config_path = os.path.join(t.dir, "gateway.toml")
        self.log_path = os.path.join(t.dir, "gateway.log")
        t.logs.append(("gateway", self.log_path))
        self.process = None
        self.write_config()

    def write_config(self, http_keys="", sensor="boom"):
        """The configuration with `http_keys` added to [http] and the sensor named `sensor`."""
        with open(self.config_path, "w") as f:
            f.write(CONFIG % dict(self._keys, http_keys=http_keys, sensor=json.dumps(sensor)))

    def start(self):
        self.process = processes.start([self.tiltgate, "run", "--config", self.config_path],
                                       stdout=open(self.log_path, "w"), stderr=subprocess.STDOUT)

    def serving(self):
        """Running, and GET /healthz answers 200."""
        if self.process.poll() is not None:
            return False
        try:
            c = http.client.HTTPConnection("127.0.0.1", self.http_port, timeout=10)
            c.request("GET", "/healthz")
            return c.getresponse().status == 200
        except OSError:
            return False
