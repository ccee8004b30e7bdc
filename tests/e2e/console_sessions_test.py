#!/usr/bin/env python3
"""When a console session ends because its account changed (issue 52, item 1;
docs/web-console.md, "When a session ends"): build/tiltgate run with accounts made by
`tiltgate user add`, each logged in, then each account changed while the gateway runs, through
`tiltgate user` (remove, passwd, role) and by editing the users file in place as an editor
does. The changed account's session gets 401 at its very next request (no wait: the file is
looked at before every /api/ request is served); everyone else's goes on; the old password
opens nothing. A malformed line is skipped (issue 54, defect 7): the others go on.

Usage: /usr/bin/python3 console_sessions_test.py path/to/tiltgate
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import Client, start_console  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402

ACCOUNTS = {  # name: (role, password)
    "keeper": ("admin", "keeper-pass-01"),
    "victim": ("admin", "victim-pass-02"),
    "newpass": ("operator", "newpass-pass-03"),
    "demoted": ("admin", "demoted-pass-04"),
    "byhand": ("admin", "byhand-pass-05"),
    "cut": ("operator", "cut-pass-0006"),
}


def user(tiltgate, users_file, *args, password=None):
    done = subprocess.run([tiltgate, "user", *args, "--users-file", users_file],
                          input=(password + "\n") if password else "", text=True,
                          capture_output=True, timeout=30)
    if done.returncode != 0:
        raise RuntimeError("tiltgate user %s: %s" % (" ".join(args), done.stderr))


def edit_in_place(path, change):
    """Rewrites the file's text through the same inode, as an editor saving in place does."""
    with open(path, "r+") as f:
        text = change(f.read())
        f.seek(0)
        f.write(text)
        f.truncate()


def scenario(t):
    tiltgate, _ = arguments()
    users_file = os.path.join(t.dir, "users")
    for name, (role, password) in ACCOUNTS.items():
        user(tiltgate, users_file, "add", name, "--role", role, password=password)
    http_port = start_console(t, tiltgate, users_file)

    clients = {}
    for name, (role, password) in ACCOUNTS.items():
        clients[name] = Client(http_port)
        status, _ = clients[name].login(name, password)
        t.check("%s logs in" % name, status == 200, status)
    keeper, victim = clients["keeper"], clients["victim"]
    t.check("victim, an admin, reads the configuration",
            victim.request("GET", "/api/config")[0] == 200)

    user(tiltgate, users_file, "remove", "victim")
    status, _ = victim.request("GET", "/api/config")
    t.check("after `tiltgate user remove victim` its next request: 401", status == 401, status)
    status, _ = victim.request("POST", "/api/sensors/boom/settings",
                               {"setting": "filter", "value": 3})
    t.check("  and it changes no setting: 401", status == 401, status)
    status, body = keeper.request("GET", "/api/audit?who=victim")
    t.check("  so the trail holds nothing done as victim",
            status == 200 and body.get("records") == [], (status, body))
    t.check("  while keeper's session goes on", keeper.request("GET", "/api/config")[0] == 200)

    newpass = clients["newpass"]
    user(tiltgate, users_file, "passwd", "newpass", password="newpass-pass-33")
    status, _ = keeper.login("keeper", ACCOUNTS["keeper"][1])
    t.check("another user logs in after `tiltgate user passwd newpass`", status == 200, status)
    status, _ = newpass.request("GET", "/api/sensors")
    t.check("  and newpass's old session: 401", status == 401, status)
    status, _ = Client(http_port).login("newpass", ACCOUNTS["newpass"][1])
    t.check("  the old password opens no session: 401", status == 401, status)
    status, _ = Client(http_port).login("newpass", "newpass-pass-33")
    t.check("  the new one does", status == 200, status)

    demoted = clients["demoted"]
    user(tiltgate, users_file, "role", "demoted", "--role", "viewer")
    status, _ = demoted.request("GET", "/api/sensors")
    t.check("after `tiltgate user role demoted --role viewer` its admin session: 401",
            status == 401, status)
    again = Client(http_port)
    status, body = again.login("demoted", ACCOUNTS["demoted"][1])
    t.check("  a new login is a viewer's", status == 200 and body.get("role") == "viewer",
            (status, body))
    t.check("  who may not read the configuration: 403",
            again.request("GET", "/api/config")[0] == 403)

    byhand = clients["byhand"]
    edit_in_place(users_file, lambda text: text.replace("byhand:admin:", "byhand:operator:"))
    status, _ = byhand.request("GET", "/api/sensors")
    t.check("after the file is edited in place to make byhand an operator: 401",
            status == 401, status)

    cut = clients["cut"]
    edit_in_place(users_file, lambda text: "".join(
        line for line in text.splitlines(True) if not line.startswith("cut:")))
    status, _ = cut.request("GET", "/api/sensors")
    t.check("after cut's line is deleted from the file in place: 401", status == 401, status)

    # A malformed line (issue 54, defect 7) is skipped, said in the log at its file:line once
    # per change of the file; every other account goes on.
    edit_in_place(users_file, lambda text: text + "not an account line\n")
    lines = open(users_file).read().count("\n")
    status, _ = keeper.request("GET", "/api/sensors")
    t.check("a malformed line appended to the users file: keeper's session still serves",
            status == 200, status)
    status, _ = Client(http_port).login("newpass", "newpass-pass-33")
    t.check("  and another account logs in", status == 200, status)
    for _ in range(3):
        keeper.request("GET", "/api/sensors")
    log = open(os.path.join(t.dir, "gateway.log")).read()
    said = "%s:%d: expected NAME:ROLE:HASH" % (users_file, lines)
    t.check("  the log names the line, once for that change of the file",
            log.count(said) == 1 and "line skipped" in log, log[-1500:])
    byhand_login = Client(http_port)
    byhand_login.login("byhand", ACCOUNTS["byhand"][1])
    t.check("  byhand logs in again", byhand_login.request("GET", "/api/sensors")[0] == 200)
    edit_in_place(users_file, lambda text: text.replace("byhand:operator:", "byhand:boss:"))
    status, _ = byhand_login.request("GET", "/api/sensors")
    t.check("an account whose line turns malformed (role boss): its session ends, 401",
            status == 401, status)
    status, _ = Client(http_port).login("byhand", ACCOUNTS["byhand"][1])
    t.check("  and it cannot log in: 401", status == 401, status)
    status, _ = keeper.request("GET", "/api/sensors")
    t.check("  while keeper's session goes on", status == 200, status)

    os.rename(users_file, users_file + ".away")
    status, _ = keeper.request("GET", "/api/sensors")
    t.check("a users file that cannot be read ends every session: 401", status == 401, status)
    status, body = Client(http_port).login("keeper", ACCOUNTS["keeper"][1])
    t.check("  and a login says no accounts can be read: 503", status == 503, (status, body))
    os.rename(users_file + ".away", users_file)
    status, _ = keeper.login("keeper", ACCOUNTS["keeper"][1])
    t.check("  once back, logins work again", status == 200, status)
    status, _ = keeper.request("GET", "/api/sensors")
    t.check("  and the session serves", status == 200, status)

if __name__ == "__main__":
    sys.exit(Checks("console-sessions").run(scenario))
