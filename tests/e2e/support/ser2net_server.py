"""Debian's ser2net as the serial device server of a test: it serves a simulator's pseudo-terminal
on a free loopback port, raw (`tcp://`) or with RFC 2217 (`rfc2217://`), from a YAML file the
test writes, and can be killed and started again on the same port mid-run.

What ser2net 4.3.11 does that shapes this (measured on Debian 12):
- it opens the device at each client connection, not at start, so a simulator restarted on a
  new /dev/pts/N behind the same link is found by the next connection;
- a port it cannot bind is logged and it keeps running without listening (and without heeding
  SIGTERM), so "something listens on the port" is not "ser2net started": this waits until the
  listening socket is one of ser2net's own descriptors;
- it listens about 20 ms after exec; a restart binds the same port again at once.
"""
import os
import signal
import subprocess

import spb_path  # noqa: F401  (spb_e2e on the import path)
from spb_e2e import processes


def listening_inode(pid, port):
    """The inode of the TCP socket listening on `port` in process `pid`'s network namespace
    (/proc/PID/net/tcp), or None."""
    try:
        f = open("/proc/%d/net/tcp" % pid)
    except OSError:
        return None
    with f:
        next(f)
        for line in f:
            fields = line.split()
            local, state, inode = fields[1], fields[3], fields[9]
            if state == "0A" and int(local.split(":")[1], 16) == port:  # 0A: LISTEN
                return inode
    return None


def holds_socket(pid, inode):
    try:
        links = [os.readlink("/proc/%d/fd/%s" % (pid, fd)) for fd in os.listdir("/proc/%d/fd" % pid)]
    except OSError:
        return False
    return "socket:[%s]" % inode in links


class Ser2net:
    """ser2net serving `device` (a path, e.g. a simulator's link) on host:port (127.0.0.1; with
    `netns`, an address of that network namespace, where it then runs: `ip netns exec`).

    mode "raw" (accepter tcp) or "rfc2217" (accepter telnet(rfc2217)); `rate` is the connector's
    rate: the one the pty keeps in raw mode, and the one it starts at in rfc2217 mode until the
    client sets another. `options` are extra connection options (e.g. {"chardelay-max": 0})."""

    def __init__(self, scratch_dir, device, rate, mode="raw", name="ser2net", options=None,
                 host="127.0.0.1", netns=None):
        if mode not in ("raw", "rfc2217"):
            raise ValueError("mode is raw or rfc2217, not %r" % mode)
        self.mode = mode
        self.host = host
        self.netns = netns
        self.port = processes.free_port()
        self.config_path = os.path.join(scratch_dir, name + ".yaml")
        self.log_path = os.path.join(scratch_dir, name + ".log")
        accepter = "tcp,%s,%d" % (host, self.port)
        if mode == "rfc2217":
            accepter = "telnet(rfc2217)," + accepter
        lines = ["connection: &%s" % name.replace("-", "_"),
                 "  accepter: " + accepter,
                 "  connector: serialdev,%s,%dn81,local" % (device, rate)]
        if options:
            lines.append("  options:")
            lines += ["    %s: %s" % (k, v) for k, v in options.items()]
        with open(self.config_path, "w") as f:
            f.write("\n".join(lines) + "\n")
        self.process = None

    @property
    def url(self):
        """The [[bus]] port that reaches it."""
        return "%s://%s:%d" % ("tcp" if self.mode == "raw" else "rfc2217", self.host, self.port)

    def start(self, wait_s=5):
        """Starts it (again) and waits until its own socket listens."""
        if self.running():
            raise RuntimeError("ser2net already runs")
        log = open(self.log_path, "a")
        argv = ["ser2net", "-n", "-d", "-c", self.config_path]
        if self.netns:
            argv = ["ip", "netns", "exec", self.netns] + argv  # which execs ser2net: one pid
        self.process = processes.start(argv, stdout=log, stderr=subprocess.STDOUT)
        pid = self.process.pid
        listening = lambda: (not self.running() or
                             holds_socket(pid, listening_inode(pid, self.port) or "none"))
        if not processes.wait_until(listening, wait_s) or not self.running():
            self.stop()
            raise RuntimeError("ser2net did not listen on port %d:\n%s" %
                               (self.port, processes.tail(self.log_path)))

    def running(self):
        return self.process is not None and self.process.poll() is None

    def kill(self):
        """kill -9, as a server losing power: its clients' connections end at once."""
        if self.running():
            self.process.send_signal(signal.SIGKILL)
            self.process.wait(timeout=10)

    def stop(self):
        """SIGTERM; SIGKILL when it does not end (ser2net that could not bind ignores TERM)."""
        if not self.running():
            return
        self.process.send_signal(signal.SIGTERM)
        try:
            self.process.wait(timeout=3)
        except subprocess.TimeoutExpired:
            self.kill()

    def restart(self):
        self.kill()
        self.start()

    def log(self):
        return processes.tail(self.log_path, 40)
