"""The processes a test starts, ended (by their own ids) when it finishes, free loopback ports and
waiting with a deadline."""
import os
import signal
import socket
import subprocess
import time

_started = []
_ports = set()


def start(argv, **kwargs):
    process = subprocess.Popen(argv, **kwargs)
    _started.append(process)
    return process


def end_all():
    for process in reversed(_started):
        if process.poll() is None:
            process.send_signal(signal.SIGTERM)
    for process in reversed(_started):
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def free_port():
    """A TCP port nothing listens on now, never one handed out before in this test (the kernel
    gives a port just freed out again)."""
    while True:
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        if port not in _ports:
            _ports.add(port)
            return port


def wait_until(predicate, timeout_s, interval_s=0.05):
    """The predicate's first true value, polled until the deadline; None when it never came.
    A deadline is generous on purpose: tests wait, they never measure."""
    deadline = time.monotonic() + timeout_s
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() >= deadline:
            return None
        time.sleep(interval_s)


def tail(path, lines=30):
    if not os.path.exists(path):
        return "(no %s)" % path
    with open(path, errors="replace") as f:
        return "".join(f.readlines()[-lines:])
