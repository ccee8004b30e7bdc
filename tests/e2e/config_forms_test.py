#!/usr/bin/env python3
"""Guided configuration (issue 54, item 2; docs/web-console.md, "Guided configuration"):
build/tiltgate run on two simulated Rieker sensors, read with Python's http.client. The forms'
keys are the configuration reference's; a text's tables read as typed, with a free unit id
proposed; a filled form becomes the text with its table added, changed or removed, every other
line kept, checked as `tiltgate check` checks it with each error at its field; the text applies
with the usual confirmation; an operator may not use the forms. Then the same in Chromium: the
Configuration tab's Add a sensor and Edit forms, and the editor's Apply.

Usage: /usr/bin/python3 config_forms_test.py path/to/tiltgate
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import PASSWORDS, Client, add_users, start_gateway, write_config  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Simulator  # noqa: E402
from spb_e2e import processes  # noqa: E402

COMMENT = "# boom: the crane's main boom, fitted 2026-03\n"


def by_field(reply):
    return {e["field"]: e["message"] for e in reply.get("errors", []) if e.get("field")}


def scenario(t):
    tiltgate, _ = arguments()
    users_file = os.path.join(t.dir, "users")
    add_users(tiltgate, users_file)
    sim = Simulator(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    modbus_port, http_port = processes.free_port(), processes.free_port()
    config = os.path.join(t.dir, "gateway.toml")
    text = write_config(config, modbus_port, http_port, sim, t.dir, users_file)
    text = text.replace("[[sensor]]\nname = \"boom\"", COMMENT + "[[sensor]]\nname = \"boom\"")
    with open(config, "w") as f:
        f.write(text)
    log_path = os.path.join(t.dir, "gateway.log")
    t.logs.append(("gateway", log_path))
    start_gateway(tiltgate, config, log_path, http_port)
    bob, alice = Client(http_port), Client(http_port)
    t.check("the admin and an operator log in",
            bob.login("bob")[0] == 200 and alice.login("alice")[0] == 200)

    status, form = bob.request("GET", "/api/config/form")
    sensor_keys = {k["key"]: k for k in form.get("sensor", [])} if status == 200 else {}
    bus_keys = {k["key"]: k for k in form.get("bus", [])} if status == 200 else {}
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs",
                           "configuration.md")) as f:
        reference = f.read()
    t.check("the form's keys are the reference's: every bus and sensor key, with its type, "
            "default, meaning and choices",
            status == 200 and {"name", "port", "protocol", "baud", "tcp_port"} <= set(bus_keys) and
            {"name", "bus", "model", "address", "unit_id", "poll_ms", "mounting.invert_x",
             "alarms.x_high"} <= set(sensor_keys) and
            sensor_keys["unit_id"]["required"] and sensor_keys["unit_id"]["type"] == "integer" and
            bus_keys["parity"]["choices"] == ["even", "odd", "none"] and
            sensor_keys["poll_ms"]["default"] == "`100`" and
            sensor_keys["poll_ms"]["meaning"] in reference, (status, sorted(sensor_keys)))

    status, tables = bob.request("POST", "/api/config/tables", {"text": text})
    sensors = {s["name"]: s for s in tables.get("sensors", [])} if status == 200 else {}
    t.check("a text's tables read as typed, and the lowest free unit id proposed",
            status == 200 and set(sensors) == {"boom", "mast"} and
            sensors["boom"]["values"]["address"] == "223" and
            sensors["boom"]["values"]["bus"] == "line1" and
            tables["buses"][0]["values"]["protocol"] == "rieker" and
            tables["free_unit_id"] == 3, (status, tables))

    jib = {"name": "jib", "bus": "line1", "model": "h6", "address": "57", "unit_id": "2",
           "poll_ms": "fast"}
    status, reply = bob.request("POST", "/api/config/form",
                                {"text": text, "action": "add", "table": "sensor", "values": jib})
    t.check("a value of the wrong type is an error at its field, and no text",
            status == 200 and not reply["ok"] and reply["text"] is None and
            by_field(reply) == {"poll_ms": '"fast" is not a whole number'}, (status, reply))
    jib["poll_ms"] = "200"
    status, reply = bob.request("POST", "/api/config/form",
                                {"text": text, "action": "add", "table": "sensor", "values": jib})
    t.check("a unit id another sensor has is check's error, at the unit_id field",
            status == 200 and not reply["ok"] and "unit_id" in by_field(reply) and
            "mast" in by_field(reply)["unit_id"], (status, reply))
    jib["unit_id"] = "3"
    status, reply = bob.request("POST", "/api/config/form",
                                {"text": text, "action": "add", "table": "sensor", "values": jib})
    added = reply.get("text") or ""
    t.check("a valid form: the text with the sensor added after the last line, nothing else "
            "changed",
            status == 200 and reply["ok"] and added.startswith(text) and
            added[len(text):] == '\n[[sensor]]\nname = "jib"\nbus = "line1"\nmodel = "h6"\n'
                                 'address = 57\nunit_id = 3\npoll_ms = 200\n', (status, reply))

    status, reply = bob.request("POST", "/api/config/form", {
        "text": added, "action": "edit", "table": "sensor", "name": "boom",
        "values": {"name": "boom", "poll_ms": "250", "mounting.invert_x": "true",
                   "address": "223"}})
    edited = reply.get("text") or ""
    t.check("an edit changes the keys that changed, in place; the comment above stays",
            status == 200 and reply["ok"] and COMMENT + "[[sensor]]\nname = \"boom\"" in edited and
            "address = 223\nunit_id = 1\npoll_ms = 250\nmounting = { invert_x = true }\n" in edited,
            (status, reply))
    status, reply = bob.request("POST", "/api/config/form", {
        "text": edited, "action": "edit", "table": "sensor", "name": "boom",
        "values": {"mounting.rotate_deg": "400"}})
    t.check("a mounting key out of range is check's error at that field",
            status == 200 and not reply["ok"] and "mounting.rotate_deg" in by_field(reply),
            (status, reply))

    status, reply = bob.request("POST", "/api/config/form", {
        "text": edited, "action": "remove", "table": "bus", "name": "line1"})
    t.check("removing a bus its sensors name: the text, and check's errors for those sensors",
            status == 200 and not reply["ok"] and "[[bus]]" not in (reply["text"] or "") and
            any("line1" in e["message"] for e in reply["errors"]), (status, reply))
    status, reply = bob.request("POST", "/api/config/form", {
        "text": edited, "action": "remove", "table": "sensor", "name": "mast"})
    t.check("removing a sensor: its lines go, the rest stays",
            status == 200 and reply["ok"] and 'name = "mast"' not in reply["text"] and
            COMMENT in reply["text"] and 'name = "jib"' in reply["text"], (status, reply))
    status, reply = bob.request("POST", "/api/config/form", {
        "text": edited, "action": "edit", "table": "sensor", "name": "ghost", "values": {}})
    t.check("an edit of a sensor the text does not have says so",
            status == 200 and not reply["ok"] and
            reply["errors"][0]["message"] == 'no [[sensor]] named "ghost"', (status, reply))
    for body, why in (({"text": text, "action": "move", "table": "sensor"}, "action"),
                      ({"text": text, "action": "add", "table": "server"}, "table"),
                      ({"text": text, "action": "edit", "table": "sensor"}, "name"),
                      ({"text": text, "action": "add", "table": "sensor", "values": {"a": 1}},
                       "values")):
        status, reply = bob.request("POST", "/api/config/form", body)
        t.check("a malformed form (%s) is 400 saying why" % why,
                status == 400 and why in reply.get("error", ""), (status, reply))

    status, reply = alice.request("GET", "/api/config/form")
    status_tables, _ = alice.request("POST", "/api/config/tables", {"text": text})
    t.check("the forms are for the admin role: an operator gets 403",
            status == 403 and status_tables == 403, (status, reply))

    # The form's text applies as the editor's does: checked again, confirmed, reloaded.
    status, reply = bob.request("PUT", "/api/config", {"text": edited, "confirm_s": 60})
    confirmed = processes.wait_until(
        lambda: bob.request("POST", "/api/config/confirm")[0] == 200, 20)
    served = processes.wait_until(
        lambda: "jib" in [s["name"] for s in bob.request("GET", "/api/sensors")[1]], 20)
    with open(config) as f:
        on_disk = f.read()
    t.check("the form's text applies, is confirmed and served: jib is a sensor now",
            status == 200 and confirmed and served and on_disk == edited, (status, reply))
    check = subprocess.run([tiltgate, "check", "--config", config], capture_output=True,
                           text=True, timeout=60)
    t.check("tiltgate check takes the file the forms made", check.returncode == 0,
            check.stdout + check.stderr)

    page = subprocess.run(
        [sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support",
                                      "chromium_page.py"),
         "forms", "http://127.0.0.1:%d/" % http_port, "bob:" + PASSWORDS["bob"], "tip", "4"],
        capture_output=True, text=True, timeout=180)
    t.check("in Chromium: Add a sensor proposes unit 4, shows a taken unit id at its field, puts "
            "its text in the editor, whose Apply shows the diff and is confirmed; Edit changes "
            "boom", page.returncode == 0, page.stdout + page.stderr)
    served = processes.wait_until(
        lambda: "tip" in [s["name"] for s in bob.request("GET", "/api/sensors")[1]], 20)
    t.check("the sensor added in the page is served", served)


if __name__ == "__main__":
    sys.exit(Checks("config-forms").run(scenario))
