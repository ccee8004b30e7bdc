#!/usr/bin/env python3
"""The web console over HTTPS (issue 42; docs/web-console.md): [http] tls_cert_file and
tls_key_file from a test CA the openssl CLI makes; Python's ssl module, trusting only that CA,
logs in and gets a Secure cookie; a plain-HTTP request to the same port is not answered; and a
gateway without HTTPS refuses a login that does not come from loopback... which a test on
loopback cannot make, so that rule is a unit test (tests/unit/console/request_guard_test.cpp).

Usage: /usr/bin/python3 console_tls_test.py path/to/tiltgate
"""
import http.client
import json
import os
import ssl
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Simulator  # noqa: E402
from spb_e2e import processes  # noqa: E402


def openssl(*args, cwd):
    subprocess.run(["openssl", *args], cwd=cwd, check=True, capture_output=True, timeout=60)


def make_certificates(folder):
    openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj", "/CN=test CA",
            "-keyout", "ca.key", "-out", "ca.crt", cwd=folder)
    openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", "/CN=localhost",
            "-keyout", "console.key", "-out", "console.csr", cwd=folder)
    with open(os.path.join(folder, "san.ext"), "w") as f:
        f.write("subjectAltName = DNS:localhost, IP:127.0.0.1\n")
    openssl("x509", "-req", "-in", "console.csr", "-CA", "ca.crt", "-CAkey", "ca.key",
            "-CAcreateserial", "-days", "2", "-extfile", "san.ext", "-out", "console.crt",
            cwd=folder)


def scenario(t):
    tiltgate, _ = arguments()
    make_certificates(t.dir)
    users = os.path.join(t.dir, "users")
    subprocess.run([tiltgate, "user", "add", "bob", "--role", "admin", "--users-file", users],
                   input="admin-pass-22\n", text=True, check=True, capture_output=True, timeout=30)
    sim = Simulator(tiltgate, t.dir)
    modbus_port, https_port = processes.free_port(), processes.free_port()
    config = os.path.join(t.dir, "gateway.toml")
    with open(config, "w") as f:
        f.write("""[server]
listen = "127.0.0.1"
port = %d
control_socket = ""
state_dir = "%s/state"

[http]
listen = "127.0.0.1"
port = %d
users_file = "%s"
tls_cert_file = "console.crt"
tls_key_file = "console.key"

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
""" % (modbus_port, t.dir, https_port, users, sim.link))
    log_path = os.path.join(t.dir, "gateway.log")
    t.logs.append(("gateway", log_path))
    gateway = processes.start([tiltgate, "run", "--config", config],
                              stdout=open(log_path, "w"), stderr=subprocess.STDOUT)
    context = ssl.create_default_context(cafile=os.path.join(t.dir, "ca.crt"))

    def https(method, path, body=None, headers=None):
        c = http.client.HTTPSConnection("127.0.0.1", https_port, timeout=10, context=context)
        c.request(method, path, body=json.dumps(body) if body is not None else None,
                  headers=headers or {})
        r = c.getresponse()
        data = r.read().decode()
        return r.status, {k.lower(): v for k, v in r.getheaders()}, data

    def up():
        if gateway.poll() is not None:
            raise RuntimeError("the gateway exited:\n" + processes.tail(log_path))
        try:
            return https("GET", "/healthz")[0] == 200
        except OSError:
            return False
    t.check("the gateway serves /healthz over HTTPS with the test CA's certificate",
            processes.wait_until(up, 20), processes.tail(log_path))
    status, headers, body = https("POST", "/api/login", {"user": "bob", "password": "admin-pass-22"},
                                  {"Content-Type": "application/json"})
    cookie = headers.get("set-cookie", "")
    t.check("a login over HTTPS: 200 and a Secure, HttpOnly, SameSite=Strict cookie",
            status == 200 and "Secure" in cookie and "HttpOnly" in cookie and
            "SameSite=Strict" in cookie, (status, cookie, body))
    t.check("HTTPS answers carry Strict-Transport-Security",
            "strict-transport-security" in headers, headers)
    token = cookie.split(";")[0]
    status, _, body = https("GET", "/api/sensors", headers={"Cookie": token})
    t.check("the session works over HTTPS", status == 200, (status, body))

    plain = http.client.HTTPConnection("127.0.0.1", https_port, timeout=5)
    try:
        plain.request("GET", "/healthz")
        answered = plain.getresponse().status == 200
    except (OSError, http.client.HTTPException):
        answered = False
    t.check("plain HTTP on the HTTPS port gets no answer", not answered)
    untrusted = ssl.create_default_context()  # the system's CAs: not the test CA
    try:
        c = http.client.HTTPSConnection("127.0.0.1", https_port, timeout=5, context=untrusted)
        c.request("GET", "/healthz")
        c.getresponse()
        verified = True
    except ssl.SSLError:
        verified = False
    t.check("a client that does not trust the test CA refuses the certificate", not verified)
    t.check("the gateway still serves after both", up())

    def tls12_handshake(suite):
        """openssl s_client offering TLS 1.2 with only `suite`: (handshake done, its output)."""
        done = subprocess.run(["openssl", "s_client", "-connect", "127.0.0.1:%d" % https_port,
                               "-tls1_2", "-cipher", suite], stdin=subprocess.DEVNULL,
                              capture_output=True, text=True, timeout=30)
        out = done.stdout + done.stderr
        return done.returncode == 0 and ("Cipher is " + suite) in out, out
    accepted, out = tls12_handshake("ECDHE-RSA-AES128-GCM-SHA256")
    t.check("TLS 1.2 with an AEAD suite (ECDHE-RSA-AES128-GCM-SHA256) is accepted", accepted, out)
    for suite in ("AES128-SHA", "ECDHE-RSA-AES128-SHA", "AES128-SHA256"):
        accepted, out = tls12_handshake(suite)
        t.check("TLS 1.2 with the CBC suite %s is refused by the gateway" % suite,
                not accepted and "alert handshake failure" in out, out)
    t.check("the gateway still serves after the refused suites", up())


if __name__ == "__main__":
    sys.exit(Checks("console-tls").run(scenario))
