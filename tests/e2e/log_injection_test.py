#!/usr/bin/env python3
"""No door writes a forged line into the gateway's log (issue 52, item 6:
docs/operations.md, "What the log shows of text from outside"). build/tiltgate run on a
simulated Rieker sensor with a console account admin1. Two doors are tried with the same text,
a newline and then a well-formed log line saying admin1 logged in:

- the web console's login, as its user name (Python's http.client);
- the configuration file, as a sensor's name, reloaded with SIGHUP (the loader's error quotes
  the name).

Each time the log must have no line that starts with the forged line, must show the text with
the newline as the two characters \\n, and the gateway must still serve.

Usage: /usr/bin/python3 log_injection_test.py path/to/tiltgate
"""
import http.client
import json
import os
import signal
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from console_gateway import ConsoleGateway  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e import processes  # noqa: E402

FORGED_LINE = "2026-12-06 03:50:00.000 info  web console: admin1 logged in"
FORGED_NAME = "x\n" + FORGED_LINE
SHOWN = "x\\n" + FORGED_LINE  # what the log should show: the newline as backslash and n



def forged_lines(log_path, since=0):
    """The log's lines from byte `since` on that start as the forged line does."""
    with open(log_path, errors="replace") as f:
        f.seek(since)
        return [line for line in f if line.startswith(FORGED_LINE)]


def log_shows(log_path, text):
    with open(log_path, errors="replace") as f:
        return text in f.read()


def scenario(t):
    tiltgate, _ = arguments()
    plant = ConsoleGateway(t, tiltgate, "admin1")
    log_path = plant.log_path
    plant.start()
    gateway = plant.process

    def request(method, path, body=None):
        c = http.client.HTTPConnection("127.0.0.1", plant.http_port, timeout=10)
        headers = {"Content-Type": "application/json"} if body is not None else {}
        c.request(method, path, body=json.dumps(body) if body is not None else None,
                  headers=headers)
        r = c.getresponse()
        return r.status, r.read().decode()

    t.check("the gateway serves", processes.wait_until(plant.serving, 20), processes.tail(log_path))

    # The console's login, its user name the forged text.
    before = os.path.getsize(log_path)
    status, body = request("POST", "/api/login", {"user": FORGED_NAME, "password": "guess"})
    t.check("a login with the forged name is refused (401)", status == 401, (status, body))
    t.check("the failed login is logged with the name's newline shown as \\n",
            processes.wait_until(lambda: log_shows(log_path, 'failed login as "%s"' % SHOWN), 5),
            processes.tail(log_path))
    t.check("the log has no forged line after the login", not forged_lines(log_path, before),
            forged_lines(log_path, before))
    t.check("the gateway still serves after the forged login", plant.serving())

    # The configuration file, a sensor's name the forged text: the reload is refused, and the
    # error quotes the name.
    plant.write_config(sensor=FORGED_NAME)
    before = os.path.getsize(log_path)
    gateway.send_signal(signal.SIGHUP)
    t.check("the reload with the forged sensor name is refused, the name shown with \\n",
            processes.wait_until(lambda: log_shows(log_path, '"%s" is not a valid name' % SHOWN),
                                 10), processes.tail(log_path))
    t.check("the log has no forged line after the reload", not forged_lines(log_path, before),
            forged_lines(log_path, before))
    t.check("the gateway still serves after the refused reload", plant.serving())

    # `tiltgate check` prints the same error on stderr, which is the journal under systemd.
    checked = subprocess.run([tiltgate, "check", "--config", plant.config_path],
                             capture_output=True, text=True, timeout=30)
    printed = checked.stdout + checked.stderr
    t.check("tiltgate check shows the forged name with \\n and prints no forged line",
            checked.returncode != 0 and SHOWN in printed and
            not any(line.startswith(FORGED_LINE) for line in printed.splitlines()), printed)


if __name__ == "__main__":
    sys.exit(Checks("log-injection").run(scenario))
