"""A plant whose lines are reached over the network: `tiltgate sim FAMILY` on a pseudo-terminal
(any family, answering only at `--baud` when given), served by a device server (ser2net_server),
and `tiltgate run` with each [[bus]] port a URL, read by a real Modbus client (pymodbus) and over
its HTTP status API.

The common block every unit serves (docs/register-maps.md): input registers 0..1 angle_x and
2..3 angle_y (float32, high word first), 6 status (bit 0 online), 15 sample_seq (+1 with every
new reading)."""
import collections
import json
import os
import signal
import struct
import subprocess
import urllib.request

import spb_path  # noqa: F401  (spb_e2e on the import path)
from spb_e2e import processes
from spb_e2e.plant import toml_value

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
RTU_PROFILE = os.path.join(SOURCE_DIR, "examples", "devices", "rtu-inclinometer.toml")


class Simulator:
    """`tiltgate sim FAMILY --sensors SPEC` on a pty behind `link`; `baud`: it hears only
    requests sent while the pty is at that rate; `protocol`: the family's --protocol."""

    def __init__(self, tiltgate, scratch_dir, family, sensors, baud=None, protocol=None,
                 name="sim"):
        self.link = os.path.join(scratch_dir, name + "-tty")
        self.err_path = os.path.join(scratch_dir, name + ".err")
        argv = [tiltgate, "sim", family]
        if protocol:
            argv += ["--protocol", protocol]
        argv += ["--sensors", sensors, "--link", self.link]
        if baud:
            argv += ["--baud", str(baud)]
        self.process = processes.start(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                       stderr=open(self.err_path, "w"), text=True, bufsize=1)
        self.process.stdout.readline()  # the pty's path
        if not processes.wait_until(lambda: os.path.exists(self.link), 5):
            raise RuntimeError("the simulator did not start:\n" + processes.tail(self.err_path))

    def command(self, line):
        """A console command (`angle 223 12.5 -3.25`, `counts 1 1250`); its answer ("ok")."""
        self.process.stdin.write(line + "\n")
        self.process.stdin.flush()
        return self.process.stdout.readline().strip()


def bus(name, port, protocol, sensors, **keys):
    """A [[bus]] and its sensors: each sensor (name, model, address, unit_id, {more keys})."""
    return {"name": name, "port": port, "protocol": protocol, "keys": keys, "sensors": sensors}


class Gateway:
    """`tiltgate run` on `buses` (bus() dicts), Modbus TCP and HTTP on free loopback ports."""

    def __init__(self, tiltgate, scratch_dir, buses, name="gateway"):
        self.tiltgate = tiltgate
        self.modbus_port = processes.free_port()
        self.http_port = processes.free_port()
        self.log_path = os.path.join(scratch_dir, name + ".log")
        self.config_path = os.path.join(scratch_dir, name + ".toml")
        lines = ["[server]", 'listen = "127.0.0.1"', "port = %d" % self.modbus_port,
                 'control_socket = ""', 'state_dir = "%s"' % os.path.join(scratch_dir, "state"),
                 "", "[http]", 'listen = "127.0.0.1"', "port = %d" % self.http_port]
        for b in buses:
            lines += ["", "[[bus]]", 'name = "%s"' % b["name"], 'port = "%s"' % b["port"],
                      'protocol = "%s"' % b["protocol"]]
            lines += ["%s = %s" % (k, toml_value(v)) for k, v in b["keys"].items()]
            for sensor_name, model, address, unit_id, more in b["sensors"]:
                lines += ["", "[[sensor]]", 'name = "%s"' % sensor_name, 'bus = "%s"' % b["name"],
                          'model = "%s"' % model, "address = %d" % address,
                          "unit_id = %d" % unit_id]
                lines += ["%s = %s" % (k, toml_value(v)) for k, v in more.items()]
        with open(self.config_path, "w") as f:
            f.write("\n".join(lines) + "\n")
        self.process = None

    def start(self):
        log = open(self.log_path, "a")
        self.process = processes.start(
            [self.tiltgate, "--log-level", "debug", "run", "--config", self.config_path],
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

    def stop(self):
        self.process.send_signal(signal.SIGTERM)
        return self.process.wait(timeout=20)

    def sensor(self, name):
        """/api/sensors/NAME as a dict; {} when the gateway does not answer."""
        try:
            return json.loads(urllib.request.urlopen(
                "http://127.0.0.1:%d/api/sensors/%s" % (self.http_port, name), timeout=5).read())
        except OSError:
            return {}

    def log(self, chars=3000):
        with open(self.log_path, errors="replace") as f:
            return f.read()[-chars:]


Reading = collections.namedtuple("Reading", "x y online seq")


class ModbusReader:
    """pymodbus (Debian's python3-pymodbus) reading a unit's angles and status, as a PLC would."""

    def __init__(self, port):
        from pymodbus.client import ModbusTcpClient
        self.client = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
        if not self.client.connect():
            raise RuntimeError("pymodbus could not connect to port %d" % port)

    def read(self, unit):
        """A unit's Reading, or None when the read fails (0x0B: offline, or stale)."""
        r = self.client.read_input_registers(0, 16, slave=unit)
        if r.isError():
            return None
        words = r.registers
        as_float = lambda i: struct.unpack(">f", struct.pack(">HH", words[i], words[i + 1]))[0]
        return Reading(as_float(0), as_float(2), bool(words[6] & 0x01), words[15])

    def online(self, unit):
        """Status bit 0 (input register 6, which reads while the sensor is offline; a read that
        takes in the angles is then answered 0x0B); None when the read fails."""
        r = self.client.read_input_registers(6, 1, slave=unit)
        return None if r.isError() else bool(r.registers[0] & 0x01)

    def angles_exception(self, unit):
        """The exception code a read of the angles gets (0x0B while offline), or None."""
        r = self.client.read_input_registers(0, 4, slave=unit)
        return getattr(r, "exception_code", None) if r.isError() else None

    def reply_timeout_ms(self, unit):
        """Input register 36: the reply wait in use for the sensor (it adapts upward after late
        replies); None when the read fails."""
        r = self.client.read_input_registers(36, 1, slave=unit)
        return None if r.isError() else r.registers[0]

    def close(self):
        self.client.close()


def close_to(value, expected, tolerance=0.01):
    return value is not None and abs(value - expected) <= tolerance
