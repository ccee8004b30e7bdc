#!/usr/bin/env python3
"""The web console's API end to end (issue 42; docs/web-console.md): build/tiltgate run on two
simulated Rieker sensors, with accounts made by `tiltgate user add`, read and driven with
Python's own http.client (a client nobody here wrote). Each role's boundary on every endpoint,
the cookie's flags, CSRF and Origin, login throttling, a setting changed (its ACK, and the audit
record), a scan and a raw frame through the control socket, the configuration checked, refused
and applied, logout, and the trail after a restart.

Usage: /usr/bin/python3 console_api_test.py path/to/tiltgate
"""
import http.client
import json
import os
import signal
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Simulator  # noqa: E402
from spb_e2e import processes  # noqa: E402

PASSWORDS = {"alice": "operator-pass-1", "bob": "admin-pass-22", "carol": "viewer-pass-333"}
ROLES = {"alice": "operator", "bob": "admin", "carol": "viewer"}


def add_users(tiltgate, users_file):
    for name, role in ROLES.items():
        done = subprocess.run([tiltgate, "user", "add", name, "--role", role,
                               "--users-file", users_file],
                              input=PASSWORDS[name] + "\n", text=True, capture_output=True,
                              timeout=30)
        if done.returncode != 0:
            raise RuntimeError("user add %s: %s" % (name, done.stderr))


class Client:
    """One browser-like client: keeps its session cookie and CSRF token."""

    def __init__(self, port, source=None):
        self.port = port
        self.source = source  # the loopback address its connections come from; None: any
        self.cookie = None
        self.csrf = None
        self.last_headers = {}

    def request(self, method, path, body=None, csrf=True, origin=None, headers=None):
        connection = http.client.HTTPConnection(
            "127.0.0.1", self.port, timeout=30,
            source_address=(self.source, 0) if self.source else None)
        sent = dict(headers or {})
        if body is not None:
            sent["Content-Type"] = "application/json"
            body = json.dumps(body) if not isinstance(body, str) else body
        if self.cookie:
            sent["Cookie"] = "tiltgate_session=" + self.cookie
        if csrf and self.csrf:
            sent["X-CSRF-Token"] = self.csrf
        if origin:
            sent["Origin"] = origin
        connection.request(method, path, body=body, headers=sent)
        response = connection.getresponse()
        data = response.read().decode()
        self.last_headers = {k.lower(): v for k, v in response.getheaders()}
        connection.close()
        try:
            parsed = json.loads(data)
        except ValueError:
            parsed = data
        return response.status, parsed

    def login(self, user, password=None):
        status, body = self.request("POST", "/api/login",
                                    {"user": user, "password": password or PASSWORDS[user]})
        if status == 200:
            cookie = self.last_headers.get("set-cookie", "")
            self.cookie = cookie.split(";")[0].split("=", 1)[1]
            self.csrf = body["csrf"]
        return status, body


def write_config(path, modbus_port, http_port, sim, scratch, users_file):
    text = """[server]
listen = "127.0.0.1"
port = %d
writes = true
control_socket = "%s/control.sock"
state_dir = "%s/state"

[http]
listen = "127.0.0.1"
port = %d
users_file = "%s"

[[bus]]
name = "line1"
port = "%s"
protocol = "rieker"

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
unit_id = 1

[[sensor]]
name = "mast"
bus = "line1"
model = "h4360"
address = 101
unit_id = 2
""" % (modbus_port, scratch, scratch, http_port, users_file, sim.link)
    with open(path, "w") as f:
        f.write(text)
    return text


def start_gateway(tiltgate, config, log_path, http_port):
    process = processes.start([tiltgate, "run", "--config", config],
                              stdout=open(log_path, "a"), stderr=subprocess.STDOUT)

    def healthy():
        if process.poll() is not None:
            raise RuntimeError("the gateway exited:\n" + processes.tail(log_path))
        try:
            c = http.client.HTTPConnection("127.0.0.1", http_port, timeout=2)
            c.request("GET", "/healthz")
            return c.getresponse().status == 200
        except OSError:
            return False
    if not processes.wait_until(healthy, 20):
        raise RuntimeError("the gateway did not start:\n" + processes.tail(log_path))
    return process


def start_console(t, tiltgate, users_file):
    """The simulator and the gateway with the console on `users_file`, their logs shown on a
    failure; the HTTP port."""
    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    modbus_port, http_port = processes.free_port(), processes.free_port()
    config = os.path.join(t.dir, "gateway.toml")
    write_config(config, modbus_port, http_port, sim, t.dir, users_file)
    log_path = os.path.join(t.dir, "gateway.log")
    t.logs.append(("gateway", log_path))
    start_gateway(tiltgate, config, log_path, http_port)
    return http_port


def by_name(items, name):
    """The item of a JSON list (/api/sensors, /api/buses) with that name, or None."""
    return next((i for i in items if i["name"] == name), None)


def listening(port):
    try:
        socket.create_connection(("127.0.0.1", port), timeout=2).close()
        return True
    except OSError:
        return False


def scenario(t):
    tiltgate, _ = arguments()
    users_file = os.path.join(t.dir, "users")
    add_users(tiltgate, users_file)
    with open(users_file) as f:
        stored = f.read()
    t.check("the users file holds no password in clear",
            not any(p in stored for p in PASSWORDS.values()) and "$argon2id$" in stored, stored)
    t.check("the users file is mode 0640", oct(os.stat(users_file).st_mode & 0o777) == "0o640",
            oct(os.stat(users_file).st_mode))

    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    modbus_port, http_port = processes.free_port(), processes.free_port()
    config = os.path.join(t.dir, "gateway.toml")
    original = write_config(config, modbus_port, http_port, sim, t.dir, users_file)
    log_path = os.path.join(t.dir, "gateway.log")
    t.logs.append(("gateway", log_path))
    gateway = start_gateway(tiltgate, config, log_path, http_port)

    anonymous = Client(http_port)
    status, body = anonymous.request("GET", "/api/session")
    t.check("/api/session without a session: 401, and says the console has accounts",
            status == 401 and body.get("accounts") is True, (status, body))
    for path in ("/api/sensors", "/api/buses", "/api/status", "/api/audit", "/api/config",
                 "/api/sensors/boom/settings", "/api/buses/line1/scan"):
        status, _ = anonymous.request("GET", path)
        t.check("GET %s without a session: 401" % path, status == 401, status)
    for path in ("/", "/healthz", "/metrics"):
        status, _ = anonymous.request("GET", path)
        t.check("GET %s stays open: 200" % path, status == 200, status)
    status, _ = anonymous.request("POST", "/api/sensors/boom/settings",
                                  {"setting": "filter", "value": 3})
    t.check("a change without a session: 401", status == 401, status)

    status, wrong = anonymous.login("alice", "not-her-password")
    status2, unknown = anonymous.login("nobody", "whatever")
    t.check("a wrong password and an unknown user get the same 401 and message",
            status == 401 and status2 == 401 and wrong == unknown, (status, wrong, status2, unknown))

    alice = Client(http_port)
    status, body = alice.login("alice")
    t.check("alice logs in as operator with a CSRF token",
            status == 200 and body.get("role") == "operator" and len(body.get("csrf", "")) == 64,
            (status, body))
    cookie = alice.last_headers.get("set-cookie", "")
    t.check("the cookie is HttpOnly, SameSite=Strict, Path=/ (not Secure: plain loopback)",
            "HttpOnly" in cookie and "SameSite=Strict" in cookie and "Path=/" in cookie and
            "Secure" not in cookie, cookie)
    status, body = alice.request("GET", "/api/session")
    t.check("/api/session with the session: user, role, csrf",
            status == 200 and body.get("user") == "alice" and body.get("csrf") == alice.csrf,
            (status, body))
    t.check("the sensors come online", processes.wait_until(
        lambda: all(s.get("online") for s in alice.request("GET", "/api/sensors")[1]), 20),
        alice.request("GET", "/api/sensors"))

    status, body = alice.request("GET", "/api/sensors/boom/settings")
    names = {s["name"]: s for s in body.get("settings", [])} if status == 200 else {}
    t.check("a sensor's settings are listed with the role each needs",
            status == 200 and names.get("filter", {}).get("role") == "operator" and
            names.get("bus_address", {}).get("role") == "admin", (status, body))

    status, body = alice.request("POST", "/api/sensors/boom/settings",
                                 {"setting": "filter", "value": 3}, csrf=False)
    t.check("a change without X-CSRF-Token: 403", status == 403, (status, body))
    status, body = alice.request("POST", "/api/sensors/boom/settings",
                                 {"setting": "filter", "value": 3},
                                 origin="http://evil.example")
    t.check("a change from a foreign Origin: 403", status == 403, (status, body))
    status, body = alice.request("POST", "/api/sensors/boom/settings",
                                 {"setting": "filter", "value": 3},
                                 origin="http://127.0.0.1:%d" % http_port)
    t.check("the operator sets boom's filter to 3: answered after the ACK",
            status == 200 and body.get("result") == "ack" and body.get("value") == 3,
            (status, body))
    status, body = alice.request("POST", "/api/sensors/boom/settings",
                                 {"setting": "bus_address", "value": 224})
    t.check("the operator may not move a sensor: 403", status == 403, (status, body))
    t.check("the command lists the values an operator may write (1, 2: zero)",
            names.get("command", {}).get("role") == "admin" and
            names.get("command", {}).get("operator_values") == [1, 2], names.get("command"))
    command = names.get("command", {})
    t.check("each setting carries its family's label (filter, bus_address, command)",
            names.get("filter", {}).get("label") == "Filter" and
            names.get("bus_address", {}).get("label") == "Bus address" and
            command.get("label") == "Command", body)
    t.check("the command's values are actions named by what they do, each with its question "
            "naming boom and the role that may press it",
            command.get("actions") == [
                {"value": 1, "name": "Zero to the current angle (until restart)",
                 "confirm": "Zero boom to its current angle? Until the sensor restarts.",
                 "role": "operator"},
                {"value": 2, "name": "Zero permanently",
                 "confirm": "Zero boom to its current angle permanently? The sensor keeps this "
                            "zero after a restart.",
                 "role": "operator"},
                {"value": 3, "name": "Restart the sensor",
                 "confirm": "Restart boom? It does not answer until it has started again.",
                 "role": "admin"}] and
            names.get("filter", {}).get("actions") == [], command)
    t.check("a Rieker reads no setting back: each is what was last written (read_back false)",
            names and all(s.get("read_back") is False for s in names.values()), body)
    status, body = alice.request("POST", "/api/sensors/boom/settings",
                                 {"setting": "command", "value": 1})
    t.check("the operator zeroes boom to its current angle (command 1): answered after the ACK",
            status == 200 and body.get("result") == "ack", (status, body))
    status, body = alice.request("POST", "/api/sensors/boom/settings",
                                 {"setting": "command", "value": 3})
    t.check("the operator may not restart a sensor (command 3): 403 naming what it may write",
            status == 403 and "an operator may write 1, 2" in body.get("error", ""),
            (status, body))
    status, body = alice.request("POST", "/api/sensors/boom/settings",
                                 {"setting": "no_such", "value": 1})
    t.check("an unknown setting: 400", status == 400, (status, body))
    status, body = alice.request("POST", "/api/sensors/boom/settings",
                                 {"setting": "filter", "value": 99})
    t.check("a value out of the setting's range: 400", status == 400, (status, body))
    sim.command("silent 101")
    status, body = alice.request("POST", "/api/sensors/mast/settings",
                                 {"setting": "filter", "value": 2})
    t.check("a sensor that does not answer: 504 or refused as offline",
            status in (504, 400) and "result" in body, (status, body))
    sim.command("answer 101")
    for path in ("/api/config", "/api/config.toml"):
        status, _ = alice.request("GET", path)
        t.check("GET %s as operator: 403" % path, status == 403, status)
    status, _ = alice.request("POST", "/api/buses/line1/scan", {})
    t.check("a scan as operator: 403", status == 403, status)
    status, _ = alice.request("POST", "/api/buses/line1/raw", {"address": 223, "function": 37})
    t.check("a raw frame as operator: 403", status == 403, status)

    carol = Client(http_port)
    carol.login("carol")
    status, _ = carol.request("GET", "/api/sensors")
    t.check("the viewer sees the sensors", status == 200, status)
    status, body = carol.request("GET", "/api/status")
    t.check("the viewer sees the gateway's own state: active, no redundant pair",
            status == 200 and body.get("role") == "active" and body.get("redundancy") is None
            and isinstance(body.get("uptime_s"), int), (status, body))
    status, _ = carol.request("POST", "/api/sensors/boom/settings",
                              {"setting": "filter", "value": 2})
    t.check("the viewer may change nothing: 403", status == 403, status)
    status, _ = carol.request("PUT", "/api/config", {"text": original})
    t.check("the viewer may not apply a configuration: 403", status == 403, status)

    bob = Client(http_port)
    bob.login("bob")
    status, body = bob.request("GET", "/api/config")
    t.check("the admin reads the served configuration",
            status == 200 and body.get("text") == original and body.get("path") == config,
            (status, body))
    broken = original.replace("port = %d" % modbus_port, "port = \"five\"", 1)
    status, body = bob.request("POST", "/api/config/check", {"text": broken})
    errors = body.get("errors", []) if isinstance(body, dict) else []
    t.check("a check reports the error at its line and column",
            status == 200 and body.get("ok") is False and errors and errors[0]["line"] == 3 and
            errors[0]["column"] > 0, (status, body))
    status, body = bob.request("PUT", "/api/config", {"text": broken})
    with open(config) as f:
        t.check("an invalid configuration is refused (422) and the file is unchanged",
                status == 422 and f.read() == original, (status, body))
    changed = original.replace('users_file = ', 'history_seconds = 300\nusers_file = ', 1)
    status, body = bob.request("PUT", "/api/config", {"text": changed})
    with open(config) as f:
        now = f.read()
    t.check("a valid configuration is applied: written, the previous one kept",
            status == 200 and now == changed and
            open(config + ".previous").read() == original, (status, body))
    t.check("and reloaded", processes.wait_until(
        lambda: "configuration reloaded from" in processes.tail(log_path, 400), 20),
        processes.tail(log_path))
    # [http] changed: its server binds again a moment after the reload's line (it waits for the
    # old one to let the port go), so the next request waits for it.
    processes.wait_until(lambda: listening(http_port), 20)

    status, body = bob.request("POST", "/api/buses/line1/scan", {"from": 100, "to": 102})
    t.check("the admin starts a scan: 202", status == 202, (status, body))
    t.check("the scan ends", processes.wait_until(
        lambda: not bob.request("GET", "/api/buses/line1/scan")[1].get("running", True), 60),
        bob.request("GET", "/api/buses/line1/scan"))
    status, body = bob.request("GET", "/api/buses/line1/scan")
    found = body.get("found", []) if isinstance(body, dict) else []
    t.check("the scan found the mast at 101, marked as configured already (no table to add)",
            status == 200 and body.get("progress") == 1 and
            any(s["address"] == 101 and s["configured_as"] == "mast" and s["config"] == ""
                for s in found), (status, body))
    status, body = bob.request("POST", "/api/buses/line1/raw", {"address": 223, "function": 37})
    t.check("a raw frame shows the bytes each way and the checksum's verdict",
            status == 200 and body.get("sent") and body.get("received") and body.get("verdict"),
            (status, body))

    status, body = carol.request("GET", "/api/audit?door=console")
    records = body.get("records", []) if isinstance(body, dict) else []
    t.check("the audit trail holds alice's filter change with its ACK",
            any(r["who"] == "alice" and r["setting"] == "filter" and r["new"] in ("3", "3.0")
                and r["result"] == "ack" for r in records), records[:6])
    t.check("and the refused address change, the configuration, the scan and the raw frame",
            any(r["setting"] == "bus_address" and r["result"].startswith("refused")
                for r in records) and
            any(r["setting"] == "config" and r["who"] == "bob" for r in records) and
            any(r["setting"] == "scan" and r["who"] == "bob" and r["result"] == "ok"
                for r in records), records[:10])
    # A raw frame the line carried is recorded from what the gateway carried, under the
    # console's door and its user: a Set Filter without the unlock, refused by the sensor
    # (NAK 4); the read above is none.
    bob.request("POST", "/api/buses/line1/raw", {"address": 223, "function": 41, "data": "02"})
    status, body = carol.request("GET", "/api/audit?door=console")
    records = body.get("records", []) if isinstance(body, dict) else []
    t.check("a raw frame that may change a sensor is one record of what the gateway carried",
            [(r["who"], r["setting"], r["new"], r["result"]) for r in records
             if r["who"] == "bob" and r["setting"].startswith("function")] ==
            [("bob", "function 41 (set filter response)", "02", "nak 0x04")], records[:6])
    status, body = carol.request("GET", "/api/audit?door=control%20socket")
    records = body.get("records", []) if isinstance(body, dict) else []
    t.check("and none under the control socket's door: the console runs it in the gateway",
            not [r for r in records if "bob" in r["who"]], records[:6])

    attacker = Client(http_port)
    codes = [attacker.login("mallory", "guess%d" % i)[0] for i in range(5)]
    status, body = attacker.login("mallory", "guess-again")
    t.check("after 4 failures the next login is throttled: 429 with Retry-After",
            codes[:4] == [401] * 4 and status == 429 and body.get("retry_after_s", 0) >= 1 and
            "retry-after" in attacker.last_headers, (codes, status, body))
    status, metrics = anonymous.request("GET", "/metrics")
    def metric(name):
        for line in metrics.splitlines():
            if line.startswith(name + " "):
                return float(line.split()[1])
        return -1
    t.check("/metrics counts the failed and the throttled logins",
            metric("tiltgate_http_login_failures_total") >= 6 and
            metric("tiltgate_http_logins_throttled_total") >= 2, metrics[-800:])

    status, _ = alice.request("POST", "/api/logout")
    after, _ = alice.request("GET", "/api/sensors")
    t.check("logout ends the session", status == 200 and after == 401, (status, after))

    gateway.send_signal(signal.SIGTERM)
    gateway.wait(timeout=20)
    gateway = start_gateway(tiltgate, config, log_path, http_port)
    carol = Client(http_port)
    carol.login("carol")
    status, body = carol.request("GET", "/api/audit?who=alice&setting=filter")
    records = body.get("records", []) if isinstance(body, dict) else []
    t.check("after a restart the trail still holds alice's change",
            status == 200 and any(r["result"] == "ack" for r in records), (status, body))
    gateway.send_signal(signal.SIGTERM)
    gateway.wait(timeout=20)


if __name__ == "__main__":
    sys.exit(Checks("console-api").run(scenario))
