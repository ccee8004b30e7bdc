#!/usr/bin/env python3
"""An apply through the web console cannot lock anyone out (issue 52, item 7;
docs/web-console.md, "Applying with a confirmation window"): `PUT /api/config` serves the new
file at once, and unless `POST /api/config/confirm` arrives through it within "confirm_s", the
previous file comes back and is reloaded; both steps are in the audit trail with what changed.
A console moved to another port is confirmed there (the old one is gone); a restart during the
window, or one that comes after its deadline, still rolls back; a second apply during a window
keeps the first one's rollback target. The apply's check refuses a [server] user that does not
exist and an address this machine does not have.

build/tiltgate run on a simulated Rieker sensor, driven with Python's own http.client.

Usage: /usr/bin/python3 console_confirm_test.py path/to/tiltgate
"""
import os
import signal
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import (Client, add_users, listening, start_gateway,  # noqa: E402
                              write_config)
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Simulator  # noqa: E402
from spb_e2e import processes  # noqa: E402


def file_text(path):
    with open(path) as f:
        return f.read()


def records(client, setting):
    status, body = client.request("GET", "/api/audit?door=console&setting=" + setting)
    return body.get("records", []) if status == 200 and isinstance(body, dict) else []


def reloads(log_path):
    return processes.tail(log_path, 2000).count("configuration reloaded from")


def scenario(t):
    tiltgate, _ = arguments()
    users_file = os.path.join(t.dir, "users")
    add_users(tiltgate, users_file)
    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    modbus_port, http_port, moved_port = (processes.free_port() for _ in range(3))
    config = os.path.join(t.dir, "gateway.toml")
    original = write_config(config, modbus_port, http_port, sim, t.dir, users_file)
    log_path = os.path.join(t.dir, "gateway.log")
    t.logs.append(("gateway", log_path))
    gateway = start_gateway(tiltgate, config, log_path, http_port)
    bob = Client(http_port)
    status, body = bob.login("bob")
    t.check("the admin logs in", status == 200, (status, body))

    status, body = bob.request("POST", "/api/config/confirm")
    t.check("a confirm with nothing applied: 409", status == 409, (status, body))
    console_at = 'listen = "127.0.0.1"\nport = %d\n' % http_port
    for key, refused in (
            ("server.user", original.replace("[server]\n", '[server]\nuser = "nosuchuser-tg"\n', 1)),
            ("http.listen", original.replace(console_at, console_at.replace("127.0.0.1",
                                                                            "192.0.2.1"), 1))):
        status, body = bob.request("PUT", "/api/config", {"text": refused, "confirm_s": 5})
        errors = body.get("errors", []) if isinstance(body, dict) else []
        t.check("an apply that could not start or serve is refused (422): %s" % key,
                status == 422 and file_text(config) == original and
                any(e["key"] == key for e in errors), (status, body))
    status, body = bob.request("PUT", "/api/config", {"text": original, "confirm_s": 2})
    t.check("a confirmation window under 5 s is refused (400)", status == 400, (status, body))

    # 1. Unconfirmed: rolled back and reloaded, both audited with what changed.
    # [server] keys: a change of [http] would restart the console's server under the requests.
    changed = original.replace("writes = true\n", "writes = true\nidle_timeout_ms = 30000\n", 1)
    before = reloads(log_path)
    status, body = bob.request("PUT", "/api/config", {"text": changed, "confirm_s": 5})
    processes.wait_until(lambda: reloads(log_path) > before, 20)
    t.check("an apply is served at once and awaits its confirmation for confirm_s",
            status == 200 and file_text(config) == changed and body.get("confirm_s") == 5 and
            body.get("console", {}).get("port") == http_port, (status, body))
    status, shown = bob.request("GET", "/api/config")
    pending = shown.get("pending") if isinstance(shown, dict) else None
    t.check("GET /api/config shows the window: who, how long is left, what changed",
            pending and pending["user"] == "bob" and 0 <= pending["seconds_left"] <= 5 and
            "sections changed: server" in pending["changes"], shown)
    applied = [r for r in records(bob, "config") if r["who"] == "bob"]
    t.check("the apply's audit record holds what changed, not the path",
            applied and "sections changed: server" in applied[0]["new"] and
            applied[0]["result"].startswith("ok: awaits confirmation"), applied[:2])
    t.check("unconfirmed, the previous file comes back", processes.wait_until(
        lambda: file_text(config) == original, 30), file_text(config))
    t.check("and is reloaded", processes.wait_until(lambda: reloads(log_path) >= before + 2, 20),
            processes.tail(log_path))
    rolled = records(bob, "config%20rollback")
    t.check("the rollback is in the audit trail with what it undid",
            rolled and rolled[0]["who"] == "bob" and "sections changed: server" in rolled[0]["old"]
            and rolled[0]["result"].startswith("ok: not confirmed within 5 s"), rolled[:2])
    t.check("no window is left open", not os.path.exists(config + ".pending") and
            bob.request("GET", "/api/config")[1].get("pending") is None)

    # 2. The console moved: the old address is gone, the new one confirms.
    moved = original.replace("port = %d\nusers_file" % http_port,
                             "port = %d\nusers_file" % moved_port, 1)
    status, body = bob.request("PUT", "/api/config", {"text": moved, "confirm_s": 60})
    t.check("an apply that moves the console answers where to confirm",
            status == 200 and body["console"]["port"] == moved_port, (status, body))
    there = Client(moved_port)
    there.cookie, there.csrf = bob.cookie, bob.csrf  # the session outlives the server's restart
    t.check("the console at the applied address confirms, once the gateway serves the file",
            processes.wait_until(
                lambda: there.request("POST", "/api/config/confirm")[0] == 200
                if listening(moved_port) else False, 30), processes.tail(log_path))
    t.check("the console at the old address cannot: it is gone", not listening(http_port))
    confirmed = records(there, "config%20confirm")
    t.check("confirmed: the file stays, the confirm is audited with what changed",
            file_text(config) == moved and not os.path.exists(config + ".pending") and
            confirmed and confirmed[0]["who"] == "bob" and
            "[http] 127.0.0.1:%d -> 127.0.0.1:%d" % (http_port, moved_port) in confirmed[0]["new"],
            confirmed[:2])
    bob = there

    # 3. A second apply during a window keeps the first one's rollback target.
    first = moved.replace("writes = true\n", "writes = true\nidle_timeout_ms = 30000\n", 1)
    second = moved.replace("writes = true\n", "writes = true\nidle_timeout_ms = 40000\n", 1)
    bob.request("PUT", "/api/config", {"text": first, "confirm_s": 60})
    status, body = bob.request("PUT", "/api/config", {"text": second, "confirm_s": 5})
    t.check("a second apply during the window is served, the last confirmed file kept",
            status == 200 and file_text(config) == second and
            file_text(config + ".previous") == moved, (status, body))
    t.check("unconfirmed, the last confirmed file comes back, not the first apply",
            processes.wait_until(lambda: file_text(config) == moved, 30), file_text(config))

    # 4. A restart during the window: the restarted gateway rolls back at the deadline.
    processes.wait_until(lambda: bob.request("GET", "/api/config")[1].get("pending") is None, 10)
    status, body = bob.request("PUT", "/api/config", {"text": first, "confirm_s": 8})
    gateway.send_signal(signal.SIGTERM)
    gateway.wait(timeout=20)
    gateway = start_gateway(tiltgate, config, log_path, moved_port)
    bob.login("bob")
    t.check("restarted during the window, it still awaits the confirmation",
            status == 200 and file_text(config) == first and os.path.exists(config + ".pending"),
            (status, body))
    t.check("and rolls back at the deadline", processes.wait_until(
        lambda: file_text(config) == moved, 30), processes.tail(log_path))

    # 5. Down past the deadline: rolled back before the file is loaded.
    status, body = bob.request("PUT", "/api/config", {"text": first, "confirm_s": 5})
    gateway.send_signal(signal.SIGTERM)
    gateway.wait(timeout=20)
    deadline = body.get("deadline_unix_s", 0) if isinstance(body, dict) else 0
    while time.time() < deadline + 1:
        time.sleep(0.2)
    t.check("stopped past the deadline, the applied file is still there",
            status == 200 and file_text(config) == first, (status, body))
    gateway = start_gateway(tiltgate, config, log_path, moved_port)
    t.check("the next start restores the previous file before serving",
            file_text(config) == moved and not os.path.exists(config + ".pending"),
            processes.tail(log_path))
    bob.login("bob")
    rolled = records(bob, "config%20rollback")
    t.check("and records it", rolled and "restored at start-up" in rolled[0]["result"], rolled[:2])
    gateway.send_signal(signal.SIGTERM)
    gateway.wait(timeout=20)


if __name__ == "__main__":
    sys.exit(Checks("console-confirm").run(scenario))
