#!/usr/bin/env python3
"""The web console's "apply" as the Debian package runs it (issue 42; docs/operations.md, "The
service and its sandbox"): the configuration's folder belongs to root and the service's group,
group-writable (0775), the configuration is root's (0640, readable by the group), and the
gateway serves as an unprivileged user of that group. `PUT /api/config` then replaces the file
whole: the new one is the service's, with the old file's mode, the old one kept beside it, and
the gateway reloads. With the folder not writable to the service, apply answers 500 saying
why, and nothing changes.

build/tiltgate run as root with [server] user = "nobody" (group nogroup, as the package's
tiltgate:tiltgate); read with Python's own http.client. Needs root to switch users: exits 77
otherwise.

Usage: /usr/bin/python3 console_apply_test.py path/to/tiltgate
"""
import grp
import http.client
import os
import pwd
import shutil
import signal
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from console_api_test import Client, add_users, start_gateway, write_config  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Simulator  # noqa: E402
from spb_e2e import processes  # noqa: E402

SERVICE_USER = "nobody"


class Unreachable(Exception):
    """The service user cannot reach the test's folder: an environment's limit, skipped."""


def scenario(t):
    tiltgate, _ = arguments()
    service = pwd.getpwnam(SERVICE_USER)
    group = service.pw_gid
    # The package's /etc/tiltgate: root:GROUP 0775, in a folder everyone may pass through.
    top = tempfile.mkdtemp(prefix="tiltgate-apply-")
    os.chmod(top, 0o755)
    try:
        # Where a folder above it is closed to others (a chroot whose root is 0700), the service
        # user cannot reach the files at all: nothing here could be shown.
        reach = subprocess.run(["setpriv", "--reuid=%d" % service.pw_uid,
                                "--regid=%d" % group, "--clear-groups", "test", "-x", top])
        if reach.returncode != 0:
            print("SKIP: user %s cannot reach %s (a folder above it is closed to others)" %
                  (SERVICE_USER, top))
            raise Unreachable()
        etc = os.path.join(top, "etc")
        os.mkdir(etc)
        os.chown(etc, 0, group)
        os.chmod(etc, 0o775)
        users_file = os.path.join(etc, "users")
        add_users(tiltgate, users_file)
        t.check("the users file takes the folder's group, so the service reads it",
                os.stat(users_file).st_gid == group, os.stat(users_file))

        sim = Simulator(tiltgate, t.dir)
        t.logs.append(("simulator", sim.err_path))
        modbus_port, http_port = processes.free_port(), processes.free_port()
        config = os.path.join(etc, "tiltgate.toml")
        original = write_config(config, modbus_port, http_port, sim, top, users_file)
        original = original.replace("[server]\n", '[server]\nuser = "%s"\n' % SERVICE_USER, 1)
        with open(config, "w") as f:
            f.write(original)
        os.chown(config, 0, group)
        os.chmod(config, 0o640)
        log_path = os.path.join(t.dir, "gateway.log")
        t.logs.append(("gateway", log_path))
        gateway = start_gateway(tiltgate, config, log_path, http_port)
        try:
            bob = Client(http_port)
            status, body = bob.login("bob")
            t.check("the admin logs in", status == 200, (status, body))

            changed = original.replace('users_file = ', 'history_seconds = 300\nusers_file = ', 1)
            status, body = bob.request("PUT", "/api/config", {"text": changed})
            st = os.stat(config)
            with open(config) as f:
                now = f.read()
            t.check("the service replaces root's configuration in its group's folder: 200",
                    status == 200 and now == changed, (status, body))
            t.check("the new file is the service's, with the old file's mode (0640)",
                    st.st_uid == service.pw_uid and oct(st.st_mode & 0o7777) == "0o640",
                    (st.st_uid, st.st_gid, oct(st.st_mode)))
            previous = config + ".previous"
            t.check("the old text is kept beside it, 0640",
                    os.path.exists(previous) and open(previous).read() == original and
                    oct(os.stat(previous).st_mode & 0o7777) == "0o640",
                    os.path.exists(previous) and oct(os.stat(previous).st_mode))
            t.check("and the gateway reloads it", processes.wait_until(
                lambda: "configuration reloaded from" in processes.tail(log_path, 400), 20),
                processes.tail(log_path))
            t.check("the window awaiting confirmation is kept beside it, the service's",
                    os.stat(config + ".pending").st_uid == service.pw_uid, os.listdir(etc))
            # The reload restarts the HTTP service ([http] changed): a request that reaches
            # the old listener as it closes is reset, and the browser's next try gets through.
            def confirmed():
                try:
                    return bob.request("POST", "/api/config/confirm")[0] == 200
                except (ConnectionError, http.client.RemoteDisconnected):
                    return False
            t.check("the admin confirms it", processes.wait_until(confirmed, 20),
                    bob.request("POST", "/api/config/confirm"))
            t.check("nothing else is left in the folder",
                    sorted(os.listdir(etc)) == ["tiltgate.toml", "tiltgate.toml.previous", "users"],
                    os.listdir(etc))

            # The folder read-only to the service (a drop-in's empty ReadWritePaths= has the
            # same effect): a clear 500, nothing changed.
            os.chmod(etc, 0o755)
            again = changed.replace("history_seconds = 300", "history_seconds = 600", 1)
            status, body = bob.request("PUT", "/api/config", {"text": again})
            with open(config) as f:
                now = f.read()
            t.check("a folder the service may not write: 500 saying why, nothing changed",
                    status == 500 and "cannot write a new file in" in body.get("error", "") and
                    "nothing was changed" in body.get("error", "") and now == changed,
                    (status, body))
        finally:
            gateway.send_signal(signal.SIGTERM)
            gateway.wait(timeout=20)
    finally:
        shutil.rmtree(top, ignore_errors=True)


if __name__ == "__main__":
    if os.geteuid() != 0:
        print("SKIP: needs root, to serve as the user %s" % SERVICE_USER)
        sys.exit(77)
    try:
        pwd.getpwnam(SERVICE_USER)
        grp.getgrgid(pwd.getpwnam(SERVICE_USER).pw_gid)
    except KeyError:
        print("SKIP: no user %s on this machine" % SERVICE_USER)
        sys.exit(77)
    checks = Checks("console-apply")
    unreachable = []

    def guarded(t):
        try:
            scenario(t)
        except Unreachable:
            unreachable.append(True)
    status = checks.run(guarded)
    sys.exit(77 if unreachable else status)
