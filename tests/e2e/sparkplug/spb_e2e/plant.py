"""The plant under test: `tiltgate sim rieker` with an H6 (boom, address 223) and an H4360
(mast, address 101) on one pseudo-terminal, taking console commands (angle, silent, answer) on
its standard input (or other sensors, on more buses), and `tiltgate run` on them with a
[sparkplug] table (or an [mqtt] one, or both), its /metrics read over HTTP."""
import os
import re
import signal
import subprocess
import urllib.request

from . import processes

SENSORS = {"boom": {"model": "h6", "address": 223, "unit_id": 1},
           "mast": {"model": "h4360", "address": 101, "unit_id": 2}}


def toml_value(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, dict):  # an inline table
        return "{ %s }" % ", ".join("%s = %s" % (k, toml_value(v)) for k, v in value.items())
    return '"%s"' % value


class Simulator:
    """`tiltgate sim rieker` with `sensors` ({name: {model, address, unit_id}}) on a pty."""

    def __init__(self, tiltgate, scratch_dir, sensors=None, name="sim"):
        self.sensors = sensors or SENSORS
        self.link = os.path.join(scratch_dir, name + "-tty")
        self.err_path = os.path.join(scratch_dir, name + ".err")
        spec = ",".join("%s:%d" % (s["model"], s["address"]) for s in self.sensors.values())
        self.process = processes.start(
            [tiltgate, "sim", "rieker", "--sensors", spec, "--link", self.link],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=open(self.err_path, "w"),
            text=True, bufsize=1)
        self.process.stdout.readline()  # the pty's path
        if not processes.wait_until(lambda: os.path.exists(self.link), 5):
            raise RuntimeError("the simulator did not start:\n" + processes.tail(self.err_path))

    def command(self, line):
        """A console command (`angle 223 12.5 -3.25`, `silent 223`, `answer 223`); its answer."""
        self.process.stdin.write(line + "\n")
        self.process.stdin.flush()
        return self.process.stdout.readline().strip()


class Gateway:
    """`tiltgate run` on the simulator's bus; `sparkplug` gives the [sparkplug] keys (None: no
    such table), `mqtt` those of an [mqtt] table."""

    def __init__(self, tiltgate, scratch_dir, simulators, sparkplug, sensor_keys=None,
                 bus_keys=None, name="gateway", mqtt=None):
        """`simulators`: one Simulator, or several, each its own [[bus]]; `sensor_keys` and
        `bus_keys` go into every [[sensor]] and [[bus]]."""
        if isinstance(simulators, Simulator):
            simulators = [simulators]
        self.tiltgate = tiltgate
        self.modbus_port = processes.free_port()
        self.http_port = processes.free_port()
        self.log_path = os.path.join(scratch_dir, name + ".log")
        self.config_path = os.path.join(scratch_dir, name + ".toml")
        lines = ["[server]", 'listen = "127.0.0.1"', "port = %d" % self.modbus_port,
                 'control_socket = ""', "", "[http]", 'listen = "127.0.0.1"',
                 "port = %d" % self.http_port]
        for table, keys in (("sparkplug", sparkplug), ("mqtt", mqtt)):
            if keys is not None:
                lines += ["", "[%s]" % table]
                lines += ["%s = %s" % (k, toml_value(v)) for k, v in keys.items()]
        for i, simulator in enumerate(simulators):
            bus = "line%d" % (i + 1)
            lines += ["", "[[bus]]", 'name = "%s"' % bus, 'port = "%s"' % simulator.link,
                      'protocol = "rieker"']
            lines += ["%s = %s" % (k, toml_value(v)) for k, v in (bus_keys or {}).items()]
            for name_, sensor in simulator.sensors.items():
                lines += ["", "[[sensor]]", 'name = "%s"' % name_, 'bus = "%s"' % bus,
                          'model = "%s"' % sensor["model"], "address = %d" % sensor["address"],
                          "unit_id = %d" % sensor["unit_id"]]
                lines += ["%s = %s" % (k, toml_value(v)) for k, v in (sensor_keys or {}).items()]
        with open(self.config_path, "w") as f:
            f.write("\n".join(lines) + "\n")
        self.process = None

    def start(self):
        log = open(self.log_path, "a")
        self.process = processes.start([self.tiltgate, "run", "--config", self.config_path],
                                       stdout=log, stderr=subprocess.STDOUT)
        if not processes.wait_until(self._healthy, 20):
            raise RuntimeError("the gateway did not start (exit %s):\n%s" %
                               (self.process.poll(), processes.tail(self.log_path)))

    def _healthy(self):
        if self.process.poll() is not None:
            raise RuntimeError("the gateway exited with %d:\n%s" %
                               (self.process.returncode, processes.tail(self.log_path)))
        try:
            return urllib.request.urlopen("http://127.0.0.1:%d/healthz" % self.http_port,
                                          timeout=2).status == 200
        except OSError:
            return False

    def running(self):
        return self.process is not None and self.process.poll() is None

    def stop(self):
        """A clean stop (SIGTERM): the gateway publishes NDEATH itself."""
        self.process.send_signal(signal.SIGTERM)
        return self.process.wait(timeout=20)

    def kill(self):
        """kill -9: the broker sends the will."""
        self.process.send_signal(signal.SIGKILL)
        self.process.wait(timeout=10)

    def log(self):
        with open(self.log_path, errors="replace") as f:
            return f.read()

    def reload(self, wait=20):
        """SIGHUP, then true once the log says the file was reloaded once more."""
        done = lambda: self.log().count("configuration reloaded from")
        before = done()
        self.process.send_signal(signal.SIGHUP)
        return processes.wait_until(lambda: done() > before, wait)

    def metrics(self):
        """/metrics as {"name{labels}": value}; {} when the gateway does not answer."""
        try:
            text = urllib.request.urlopen("http://127.0.0.1:%d/metrics" % self.http_port,
                                          timeout=5).read().decode()
        except OSError:
            return {}
        values = {}
        for line in text.splitlines():
            m = re.match(r"^([a-zA-Z_:][\w:]*(?:\{[^}]*\})?) (\S+)$", line)
            if m:
                values[m.group(1)] = float(m.group(2))
        return values

    def metric(self, name, default=None, **labels):
        """The sum of the series of `name` that have these labels (and maybe more, such as the
        store's feed); `default` when there is none."""
        found = None
        for series, value in self.metrics().items():
            base, _, rest = series.partition("{")
            if base != name:
                continue
            have = dict(re.findall(r'(\w+)="([^"]*)"', rest))
            if all(have.get(k) == v for k, v in labels.items()):
                found = (found or 0) + value
        return default if found is None else found

    def sensor_api(self, name):
        import json
        return json.loads(urllib.request.urlopen(
            "http://127.0.0.1:%d/api/sensors/%s" % (self.http_port, name), timeout=5).read())
