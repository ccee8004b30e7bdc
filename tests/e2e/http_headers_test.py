#!/usr/bin/env python3
"""The headers every HTTP answer carries and the Host check (issue 52, item 8:
docs/web-console.md, "Headers and host names"), against build/tiltgate run with the
web console on, with Python's http.client and raw sockets:

- a Content-Security-Policy that allows scripts and styles from the gateway only (no
  'unsafe-inline'), and Referrer-Policy: no-referrer, on the page, its script and style sheet,
  the API and an error;
- a request whose Host names another server (a DNS rebinding page) is answered 421 and reaches
  no route, a login included; one without Host 400; the listen address, localhost and the
  machine's name are accepted by default;
- with [http] server_names written (applied by a reload), those names only, and the address
  the request came in on.

Usage: /usr/bin/python3 http_headers_test.py path/to/tiltgate
"""
import http.client
import json
import os
import signal
import socket
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from console_gateway import ConsoleGateway  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e import processes  # noqa: E402


def scenario(t):
    tiltgate, _ = arguments()
    plant = ConsoleGateway(t, tiltgate, "bob")
    port = plant.http_port
    log_path = plant.log_path
    plant.start()
    gateway = plant.process

    def request(method, path, host=None, body=None):
        """(status, headers with lower-case names, body); `host` replaces the Host header."""
        c = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
        c.putrequest(method, path, skip_host=host is not None)
        if host is not None:
            c.putheader("Host", host)
        data = json.dumps(body).encode() if body is not None else None
        if data is not None:
            c.putheader("Content-Type", "application/json")
            c.putheader("Content-Length", str(len(data)))
        c.endheaders(data)
        r = c.getresponse()
        return r.status, {k.lower(): v for k, v in r.getheaders()}, r.read().decode()

    t.check("the gateway serves", processes.wait_until(plant.serving, 20),
            processes.tail(log_path))

    # The headers, on every kind of answer.
    for path, kind in (("/", "text/html"), ("/status_page.js", "text/javascript"),
                       ("/status_page.css", "text/css"), ("/api/sensors", "application/json"),
                       ("/no-such-page", "text/plain")):
        status, headers, _ = request("GET", path)
        policy = headers.get("content-security-policy", "")
        t.check("%s: %s, with a Content-Security-Policy of the gateway's own scripts and "
                "styles only, and Referrer-Policy: no-referrer" % (path, kind),
                headers.get("content-type", "").startswith(kind) and
                "script-src 'self'" in policy and "style-src 'self'" in policy and
                "default-src 'none'" in policy and "frame-ancestors 'none'" in policy and
                "unsafe-inline" not in policy and "unsafe-eval" not in policy and
                headers.get("referrer-policy") == "no-referrer", (status, headers))
    _, _, page = request("GET", "/")
    t.check("the page loads its script and style sheet as files and holds no inline script",
            '<script src="/status_page.js"></script>' in page and "<script>" not in page and
            "<style" not in page and " style=" not in page, page[:400])

    # The Host check: a DNS rebinding page's name.
    status, headers, body = request("GET", "/api/sensors", host="attacker.example:%d" % port)
    t.check("a request whose Host is another name is answered 421, saying why",
            status == 421 and "server_names" in body and "attacker.example" in body,
            (status, body))
    status, headers, body = request("POST", "/api/login", host="attacker.example:%d" % port,
                                    body={"user": "bob", "password": "admin-pass-22"})
    t.check("a login under another Host is answered 421 and opens no session",
            status == 421 and "set-cookie" not in headers, (status, headers, body))
    t.check("that login never reached the console (no login in the log)",
            "bob logged in" not in open(log_path).read(), processes.tail(log_path))
    t.check("the refused Host is logged",
            processes.wait_until(lambda: 'Host "attacker.example:%d" is not among [http] '
                                 'server_names' % port in open(log_path).read(), 5),
            processes.tail(log_path))
    with socket.create_connection(("127.0.0.1", port), timeout=10) as raw:
        raw.sendall(b"GET /healthz HTTP/1.0\r\n\r\n")
        answer = b""
        while True:
            chunk = raw.recv(4096)
            if not chunk:
                break
            answer += chunk
    t.check("a request without a Host header is answered 400",
            answer.startswith(b"HTTP/1.0 400") and b"Host header" in answer, answer[:200])
    for host in ("127.0.0.1:%d" % port, "localhost:%d" % port, "LocalHost",
                 socket.gethostname()):
        status, _, body = request("GET", "/healthz", host=host)
        t.check("by default Host %s is accepted" % host, status == 200, (status, body))
    status, _, body = request("POST", "/api/login", host="localhost:%d" % port,
                              body={"user": "bob", "password": "admin-pass-22"})
    t.check("a login under Host localhost works", status == 200, (status, body))

    # [http] server_names written, applied by a reload.
    plant.write_config('server_names = ["gw-3.plant.example"]')
    gateway.send_signal(signal.SIGHUP)

    def named_only():
        try:
            return request("GET", "/healthz", host="localhost")[0] == 421
        except OSError:
            return False
    t.check("with server_names = [\"gw-3.plant.example\"] Host localhost is answered 421",
            processes.wait_until(named_only, 20), processes.tail(log_path))
    status, _, body = request("GET", "/healthz", host="gw-3.plant.example:%d" % port)
    t.check("and Host gw-3.plant.example is accepted", status == 200, (status, body))
    status, _, body = request("GET", "/healthz", host="127.0.0.1:%d" % port)
    t.check("and the address the request came in on still is", status == 200, (status, body))
    t.check("the gateway still serves", gateway.poll() is None and
            request("GET", "/healthz", host="127.0.0.1")[0] == 200)


if __name__ == "__main__":
    sys.exit(Checks("http-headers").run(scenario))
