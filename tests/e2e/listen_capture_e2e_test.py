#!/usr/bin/env python3
"""Listening only (issue 55, items 4 and 8; docs/diagnostics.md, "Listening only"): a line that
another process drives, heard by `tiltgate capture --port`. build/tiltgate runs a Rieker bus
through a hub of pseudo-terminals: every byte the gateway sends reaches the simulated sensors
and the listener's pty, every byte the sensors send reaches the gateway and the listener's pty,
and every byte the listener's pty gives back is counted (a transmitting listener would collide
with the master on a real line). The listener's pcapng, read by tshark with the project's Lua
dissector: every request paired with its reply, every CRC good, and not one byte sent.

Usage: /usr/bin/python3 listen_capture_e2e_test.py path/to/tiltgate
"""
import os
import select
import shutil
import subprocess
import sys
import threading
import tty

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import Gateway, Simulator, bus  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from tshark_fields import tshark_fields  # noqa: E402


class Hub:
    """The gateway's pty and the listener's, joined to the simulator's tty as one line."""

    def __init__(self, device_path):
        self.master_side, master_slave = os.openpty()
        self.listener_side, listener_slave = os.openpty()
        for fd in (master_slave, listener_slave):
            tty.setraw(fd)
        self.master_path = os.ttyname(master_slave)
        self.listener_path = os.ttyname(listener_slave)
        self._keep = (master_slave, listener_slave)  # open: a pty without its slave hangs up
        self.device = os.open(device_path, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(self.device)
        self.from_listener = 0
        self.stopping = False
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        fds = [self.master_side, self.device, self.listener_side]
        while not self.stopping:
            ready, _, _ = select.select(fds, [], [], 0.1)
            for fd in ready:
                try:
                    data = os.read(fd, 4096)
                except OSError:
                    continue
                if fd == self.master_side:
                    os.write(self.device, data)
                    os.write(self.listener_side, data)
                elif fd == self.device:
                    os.write(self.master_side, data)
                    os.write(self.listener_side, data)
                else:
                    self.from_listener += len(data)

    def stop(self):
        self.stopping = True
        self.thread.join(2)


def scenario(t):
    tiltgate, _ = arguments()
    if not shutil.which("tshark"):
        t.check("tshark is installed (Debian package tshark; run scripts/setup)", False)
        return
    sim = Simulator(tiltgate, t.dir, "rieker", "h6:223,h4360:101", name="rieker")
    t.logs.append(("simulator", sim.err_path))
    hub = Hub(sim.link)
    gateway = Gateway(tiltgate, t.dir, [
        bus("line1", hub.master_path, "rieker", [("boom", "h6", 223, 1, {"poll_ms": 100}),
                                                 ("mast", "h4360", 101, 2, {"poll_ms": 100})]),
    ])
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    t.check("the gateway polls both sensors through the hub",
            wait_until(lambda: gateway.sensor("boom").get("online") and
                       gateway.sensor("mast").get("online"), 20))

    out = os.path.join(t.dir, "heard.pcapng")
    done = subprocess.run([tiltgate, "capture", "--port", hub.listener_path, "--protocol",
                           "rieker", "--baud", "125000", "--seconds", "3", "--output", out],
                          capture_output=True, text=True, timeout=60)
    t.check("a listen-only capture of 3 s ends with exit 0", done.returncode == 0, done.stderr)
    t.check("its summary counts requests and the replies paired with them",
            "replies paired" in done.stderr, done.stderr)
    t.check("the listener's pty gave back not one byte: nothing was transmitted",
            hub.from_listener == 0, hub.from_listener)

    rows = tshark_fields(out, ["frame.p2p_dir", "tiltgate_rieker.crc.status", "frame.comment",
                               "_ws.col.Info"], t.dir)
    requests = [r for r in rows if r[0] == "0"]
    replies = [r for r in rows if r[0] == "1"]
    t.check("the capture holds 3 s of both sensors' polls", len(requests) >= 40, len(rows))
    t.check("every CRC is good", rows and all(r[1] == "1" for r in rows), rows[:4])
    t.check("every request but the last is paired with its reply",
            len(replies) >= len(requests) - 1 and
            all("no reply" not in r[2] for r in requests[:-1]), [r for r in rows if "no" in r[2]])
    t.check("the Lua dissector names each request's function and address",
            any("Request: addr 223, Get Angle" in r[3] for r in requests) and
            any("Request: addr 101, Get Angle" in r[3] for r in requests), requests[:3])
    t.check("the gateway polled on throughout, the listener unseen",
            gateway.sensor("boom").get("online") and hub.from_listener == 0)
    gateway.stop()
    hub.stop()


if __name__ == "__main__":
    sys.exit(Checks("listen-capture").run(scenario))
