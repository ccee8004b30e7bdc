#!/usr/bin/env python3
"""Every refused attempt at a change through the web console is one audit record with its reason
(issue 52, item 3; docs/web-console.md, "The audit trail"): build/tiltgate with accounts made
by `tiltgate user add`, driven with Python's http.client. A viewer's and an operator's attempts
at PUT /api/config, POST /api/config/confirm, a scan and a raw frame are each refused (403) and
each leave exactly one record, door "console", with the user's name and "refused: " and the
reply's reason; the admin's bodies that are not what the endpoint takes (400) likewise; what
changes nothing (the GETs, a check of a configuration text) leaves no record.

Usage: /usr/bin/python3 console_refusals_test.py path/to/tiltgate
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import Client, add_users, start_console  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402

CONFIG_TEXT = {"text": "[server]\nport = 5020\n"}
SCAN = {"from": 100, "to": 102}
RAW = {"address": 223, "function": 37}


def console_records(client):
    status, body = client.request("GET", "/api/audit?door=console&limit=10000")
    if status != 200 or not isinstance(body, dict):
        raise RuntimeError("GET /api/audit: %s %s" % (status, body))
    return body["records"]


def scenario(t):
    tiltgate, _ = arguments()
    users_file = os.path.join(t.dir, "users")
    add_users(tiltgate, users_file)
    http_port = start_console(t, tiltgate, users_file)
    clients = {}
    for name in ("alice", "bob", "carol"):  # operator, admin, viewer
        clients[name] = Client(http_port)
        status, _ = clients[name].login(name)
        t.check("%s logs in" % name, status == 200, status)
    bob = clients["bob"]

    before = console_records(bob)
    for name in ("carol", "alice"):
        client = clients[name]
        for method, path, body in (("GET", "/api/config", None),
                                   ("GET", "/api/config.toml", None),
                                   ("POST", "/api/config/check", CONFIG_TEXT),
                                   ("GET", "/api/buses/line1/scan", None),
                                   ("GET", "/api/audit", None)):
            client.request(method, path, body)
    t.check("what changes nothing leaves no record (GETs, a check of a configuration)",
            console_records(bob) == before, console_records(bob)[:6])

    expected = (  # method, path, body, setting, new value, the reply's reason
        ("PUT", "/api/config", CONFIG_TEXT, "config", "",
         "the configuration is for the admin role"),
        ("POST", "/api/config/confirm", None, "config confirm", "",
         "the configuration is for the admin role"),
        ("POST", "/api/buses/line1/scan", SCAN, "scan", "100..102",
         "a scan is for the admin role"),
        ("POST", "/api/buses/line1/raw", RAW, "raw", "address 223 function 37 data -",
         "raw frames are for the admin role"),
    )
    for name, role in (("carol", "viewer"), ("alice", "operator")):
        client = clients[name]
        for method, path, body, setting, new, reason in expected:
            status, reply = client.request(method, path, body)
            t.check("%s %s as %s: 403 saying why" % (method, path, role),
                    status == 403 and reply.get("error") == reason, (status, reply))
            mine = [r for r in console_records(bob)
                    if r["who"] == name and r["setting"] == setting]
            # The configuration's refusal names the role; the bus's says what the reply says.
            result = ("refused: the %s role may not change the configuration" % role
                      if setting.startswith("config") else "refused: " + reason)
            t.check("and exactly one record of it: %s, %s, %s" % (name, setting, result),
                    len(mine) == 1 and mine[0]["result"] == result and mine[0]["new"] == new and
                    mine[0]["sensor"] == ("line1" if path.startswith("/api/buses/") else ""),
                    mine)

    for path, body, setting, reason in (
            ("/api/config", "not json", "config", "the body is not JSON"),
            ("/api/config", {"text": "[server]\n", "confirm_s": 1}, "config",
             "\"confirm_s\" is 1, expected 5 to 3600 seconds"),
            ("/api/buses/line1/scan", {"from": "one"}, "scan", "\"from\" is not a whole number"),
            ("/api/buses/line1/raw", {"address": 223}, "raw", "\"function\" is missing"),
            ("/api/sensors/boom/settings", {"setting": "nosuch", "value": 1}, "nosuch",
             "nosuch is not a setting of boom's map; its settings are "),
            ("/api/sensors/boom/settings", {"setting": "fitler", "value": 1}, "fitler",
             "fitler is not a setting of boom's map; did you mean filter?"),
            ("/api/sensors/boom/settings", {"setting": "filter", "value": 1000}, "filter",
             "filter = 1000 is outside its range, ")):
        before = [r for r in console_records(bob) if r["who"] == "bob"]
        status, reply = bob.request("PUT" if path == "/api/config" else "POST", path, body)
        after = [r for r in console_records(bob) if r["who"] == "bob"]
        added = after[:len(after) - len(before)]
        # A reason that ends in a space is the start of the message (a list, a range follows).
        said = reply.get("error") or ""
        matches = said.startswith(reason) if reason.endswith(" ") else said == reason
        t.check("the admin's body the endpoint does not take: 400 saying why (%s)" % reason,
                status == 400 and matches, (status, reply))
        t.check("and exactly one record of it, refused with the reason (%s)" % reason,
                len(added) == 1 and added[0]["setting"] == setting and
                added[0]["result"] == "refused: " + said, added)


if __name__ == "__main__":
    sys.exit(Checks("console-refusals").run(scenario))
