#!/usr/bin/env python3
"""Logins cannot be turned against their owners (issue 52, item 5; docs/web-console.md,
"Logins and guessing"): build/tiltgate run with accounts made by `tiltgate user add`, attacked
over loopback from addresses of their own (127.0.0.2 and up: Linux routes all of 127/8 here).

- an attacker guessing the owner's password from two addresses as fast as it is let: the owner,
  from an address with no failures, gets in at the first try (well within 10 s);
- 16 wrong passwords sent at once for one account from one address: at most 4 are checked, the
  rest 429; from 16 addresses: at most 10 (the account's guesses a minute);
- a viewer logging in 260 times does not log the admin out;
- a body of 512 KiB without a session: 413 before it is read; with an admin's session the
  configuration check still takes 100 KiB;
- 16 clients flooding made-up logins from rotating addresses: every API call of a logged-in admin
  is answered, and the owner's logins succeed.

Usage: /usr/bin/python3 console_logins_test.py path/to/tiltgate
"""
import http.client
import json
import os
import socket
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import Client, start_console  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402

ACCOUNTS = {"owner": ("admin", "owner-pass-0001"), "watcher": ("viewer", "watcher-pass-02"),
            "target": ("operator", "target-pass-003")}


def From(port, address):
    """A Client whose connections come from one loopback address."""
    return Client(port, source=address)


def raw_post(port, path, body, address="127.0.0.1", cookie=None, csrf=None):
    """POSTs `body` bytes; the status, or 0 when the server closed before answering."""
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30,
                                            source_address=(address, 0))
    headers = {"Content-Type": "application/json"}
    if cookie:
        headers["Cookie"] = "tiltgate_session=" + cookie
    if csrf:
        headers["X-CSRF-Token"] = csrf
    try:
        connection.request("POST", path, body=body, headers=headers)
        return connection.getresponse().status
    except OSError:
        return 0
    finally:
        connection.close()


def announced_body(port, path, length):
    """Sends a request's header announcing `length` bytes of body, and 1 KiB of it, then waits
    for an answer: the status, or 0 when none came (the server waits for the rest)."""
    with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
        s.sendall(("POST %s HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nContent-Type: application/json\r\n"
                   "Content-Length: %d\r\n\r\n" % (path, port, length)).encode() + b"x" * 1024)
        try:
            answer = s.recv(1024).decode(errors="replace")
        except OSError:
            return 0
        parts = answer.split(" ", 2)
        return int(parts[1]) if len(parts) > 1 and parts[1].isdigit() else 0


def in_parallel(count, work):
    """Runs work(i) for i in range(count) on threads released together; their results."""
    results = [None] * count
    start = threading.Barrier(count)

    def run(i):
        start.wait()
        results[i] = work(i)
    threads = [threading.Thread(target=run, args=(i,)) for i in range(count)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return results


def owner_against_guessing(t, port):
    stop = threading.Event()
    tries = {"checked": 0, "refused": 0}

    def guess(address):
        attacker = From(port, address)
        n = 0
        while not stop.is_set():
            status, _ = attacker.login("owner", "guess-%s-%d" % (address, n))
            n += 1
            tries["checked" if status == 401 else "refused"] += 1
            if status == 429:
                time.sleep(0.05)  # as fast as it is let, without spinning
    attackers = [threading.Thread(target=guess, args=(a,)) for a in ("127.0.0.2", "127.0.0.3")]
    for thread in attackers:
        thread.start()
    time.sleep(3)
    started = time.monotonic()
    status, body = From(port, "127.0.0.9").login("owner", ACCOUNTS["owner"][1])
    took = time.monotonic() - started
    stop.set()
    for thread in attackers:
        thread.join()
    t.check("under guessing from two addresses, the owner from a clean one gets in at once",
            status == 200 and took < 10, (status, body, took, tries))
    t.check("  while the guesses checked stayed at most 10 (a minute's worth)",
            0 < tries["checked"] <= 10 and tries["refused"] > 0, tries)


def login_within(port, seconds):
    """The owner's login from a clean address, tried again at once when its new connection was
    closed to make room for another (as a browser does); its last status."""
    deadline = time.monotonic() + seconds
    status = 0
    while time.monotonic() < deadline:
        try:
            status = From(port, "127.0.0.9").login("owner", ACCOUNTS["owner"][1])[0]
        except (OSError, http.client.HTTPException):
            continue
        if status == 200:
            break
    return status


def scenario(t):
    tiltgate, _ = arguments()
    users_file = os.path.join(t.dir, "users")
    for name, (role, password) in ACCOUNTS.items():
        subprocess.run([tiltgate, "user", "add", name, "--role", role, "--users-file", users_file],
                       input=password + "\n", text=True, check=True, capture_output=True,
                       timeout=30)
    port = start_console(t, tiltgate, users_file)

    owner_against_guessing(t, port)

    wrong = json.dumps({"user": "target", "password": "not-the-password"})
    codes = in_parallel(16, lambda i: raw_post(port, "/api/login", wrong, "127.0.0.20"))
    # 8 connections an address ([http] max_clients_per_host): the others are closed (0).
    t.check("16 wrong passwords at once from one address: at most 4 checked, the rest 429 or "
            "closed", 0 < codes.count(401) <= 4 and
            codes.count(401) + codes.count(429) + codes.count(0) == 16, codes)
    codes = in_parallel(16, lambda i: raw_post(port, "/api/login", wrong, "127.0.0.%d" % (30 + i)))
    t.check("16 at once from 16 addresses: at most 10 checked, the rest 429",
            codes.count(401) <= 10 and codes.count(401) + codes.count(429) == 16, codes)

    admin = From(port, "127.0.0.9")
    status, _ = admin.login("owner", ACCOUNTS["owner"][1])
    t.check("the admin logs in", status == 200, status)
    watcher = From(port, "127.0.0.10")
    statuses = [watcher.login("watcher", ACCOUNTS["watcher"][1])[0] for _ in range(260)]
    t.check("a viewer logs in 260 times", statuses.count(200) == 260,
            {s: statuses.count(s) for s in set(statuses)})
    t.check("  and the admin's session goes on", admin.request("GET", "/api/config")[0] == 200)

    status = announced_body(port, "/api/login", 512 * 1024)
    t.check("512 KiB announced to /api/login without a session: 413 before it is sent",
            status == 413, status)
    status = announced_body(port, "/api/config/check", 100 * 1024)
    t.check("100 KiB announced to /api/config/check without a session: 413", status == 413, status)
    status = raw_post(port, "/api/login", b'{"user": "owner", "password": "' + b"a" * 5000 + b'"}')
    t.check("5 KB sent whole to /api/login: 413", status == 413, status)
    text = json.dumps({"text": "# " + "x" * (100 * 1024) + "\n"})
    status = raw_post(port, "/api/config/check", text, "127.0.0.9", admin.cookie, admin.csrf)
    t.check("100 KiB with an admin's session is read and checked", status in (200, 400), status)

    stop = threading.Event()
    flooded = {"requests": 0}

    def flood(i):
        n = 0
        while not stop.is_set():
            address = "127.0.1.%d" % (1 + (i * 16 + n) % 250)
            raw_post(port, "/api/login", json.dumps({"user": "made-up-%d-%d" % (i, n),
                                                     "password": "x" * 12}), address)
            flooded["requests"] += 1
            n += 1
    # The admin's browser, connected and logged in before the flood comes.
    keepalive = http.client.HTTPConnection("127.0.0.1", port, timeout=30,
                                           source_address=("127.0.0.9", 0))
    keepalive.request("GET", "/api/session", headers={"Cookie": "tiltgate_session=" + admin.cookie})
    keepalive.getresponse().read()
    flooders = [threading.Thread(target=flood, args=(i,)) for i in range(16)]
    for thread in flooders:
        thread.start()
    time.sleep(1)
    answered, asked, logins = 0, 0, []

    def owner_logins():
        for _ in range(5):
            logins.append(login_within(port, 10))
    owner = threading.Thread(target=owner_logins)
    owner.start()
    for i in range(40):
        asked += 1
        try:
            keepalive.request("GET", "/api/sensors",
                              headers={"Cookie": "tiltgate_session=" + admin.cookie})
            response = keepalive.getresponse()
            response.read()
            answered += response.status == 200
        except (OSError, http.client.HTTPException):
            keepalive.close()
            keepalive = http.client.HTTPConnection("127.0.0.1", port, timeout=30,
                                                   source_address=("127.0.0.9", 0))
        time.sleep(0.1)  # a page refreshing its view
    owner.join()
    stop.set()
    for thread in flooders:
        thread.join()
    t.check("16 clients flooding made-up logins: every API call of the admin answered",
            answered == asked, (answered, asked, flooded))
    t.check("  and each of the owner's 5 logins meanwhile succeeds within 10 s",
            logins == [200] * 5, logins)


if __name__ == "__main__":
    sys.exit(Checks("console-logins").run(scenario))
