"""The processes a test starts, ended (by their own ids) when it finishes, free loopback ports and
waiting with a deadline."""
import fcntl
import os
import random
import signal
import socket
import subprocess
import time

_started = []
_ports = set()
_claims = []


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
    """A TCP port nothing listens on now, below the kernel's ephemeral range (32768 up) so no
    connect() on the machine takes it before the test's server binds it, claimed by an flock on
    /tmp/tiltgate-test-ports/PORT while it is one of this test's last 64 (tests running side by
    side never choose the same one), never handed out twice in one test."""
    claims = "/tmp/tiltgate-test-ports"
    os.makedirs(claims, exist_ok=True)
    try:
        os.chmod(claims, 0o1777)
    except OSError:
        pass
    for _ in range(1000):
        port = random.randint(20000, 32767)
        if port in _ports:
            continue
        try:
            claim = os.open(os.path.join(claims, str(port)), os.O_RDONLY | os.O_CREAT, 0o644)
        except OSError:
            continue
        try:
            fcntl.flock(claim, fcntl.LOCK_EX | fcntl.LOCK_NB)
            with socket.socket() as s:
                s.bind(("127.0.0.1", port))
        except OSError:
            os.close(claim)
            continue
        _ports.add(port)
        _claims.append(claim)
        if len(_claims) > 64:
            os.close(_claims.pop(0))
        return port
    raise RuntimeError("no free TCP port in 20000-32767")


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
