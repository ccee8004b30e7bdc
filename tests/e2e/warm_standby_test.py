#!/usr/bin/env python3
"""A warm standby on the same line (issue 56, docs/operations.md "Warm standby"): one simulated
RS485 line with two master ports (`tiltgate sim rieker --second-master`), a primary gateway on
one and a standby on the other, the same configuration but [redundancy] role. Read with pymodbus
as a PLC would:

- the standby serves every unit warm from what it hears (the angles right, online, the reading's
  age within the primary's poll period plus 50 ms), status bit 7 and discrete input 8 say
  standby, /api/status says so, and it transmits nothing (the simulator's byte count of its
  port stays 0) while the primary runs;
- a write on the standby is refused (0x0A) and nothing is sent;
- SIGSTOP of the primary for longer than takeover_ms: the standby takes the line (its first
  request measured against the primary's last), the PLC reading through it sees fresh readings;
  SIGCONT: the old primary stands down (it was held up) instead of fighting, and listens;
- SIGKILL of whichever is active: the other takes over;
- a reload of the active gateway keeps it active; one that changes [redundancy] is refused;
- no collision on the line in the whole test.

Usage: /usr/bin/python3 warm_standby_test.py path/to/tiltgate
"""
import os
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import ModbusReader, close_to  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402
from standby_pair import (POLL_MS, SANITIZED, SLACK_S, TAKEOVER_MS, TwoMasterSim,  # noqa: E402
                          age_of, make_pair, role, status)

ANGLES = {223: (12.5, -3.25), 224: (-4.0, 7.5)}


def scenario(t):
    tiltgate, _ = arguments()
    sim = TwoMasterSim(tiltgate, t.dir)
    t.logs.append(("simulator", sim.err_path))
    for address, (x, y) in ANGLES.items():
        t.check("the simulator takes the angles of %d" % address,
                sim.command("angle %d %s %s" % (address, x, y)) == "ok")
    primary, standby = make_pair(t, tiltgate, sim)
    checked = subprocess.run([tiltgate, "check", "--config", standby.config_path],
                             capture_output=True, text=True)
    t.check("tiltgate check accepts the standby's configuration", checked.returncode == 0,
            checked.stdout + checked.stderr)

    primary.start()
    t.check("the primary, alone on the line, takes it after takeover_ms",
            wait_until(lambda: role(primary) == "active", 10), (status(primary), primary.log()))
    standby.start()
    plc_primary = ModbusReader(primary.modbus_port)
    plc = ModbusReader(standby.modbus_port)

    def warm(unit, address):
        got = plc.read(unit)
        x, y = ANGLES[address]
        return got is not None and got.online and close_to(got.x, x) and close_to(got.y, y)

    for unit, address in enumerate(ANGLES, 1):
        t.check("the standby serves unit %d warm: online, its angles as the sensor's" % unit,
                wait_until(lambda: warm(unit, address), 10), (plc.read(unit), standby.log()))
    t.check("/api/status on the standby: role standby",
            role(standby) == "standby", status(standby))
    r = plc.client.read_input_registers(6, 2, slave=1)
    t.check("the standby's status word has bit 7 (standby) set",
            not r.isError() and r.registers[0] & 0x80 != 0, r)
    # The same unit read on both, one right after the other: a standby as warm as the primary
    # is at most 50 ms behind it, however busy the machine running the test is.
    pairs = []
    for _ in range(30):  # a little over a second, out of step with the polls
        pairs.append((age_of(plc_primary, 1), age_of(plc, 1)))
        time.sleep(0.037)
    behind = [s - p for p, s in pairs if p is not None and s is not None]
    ages = sorted(s for _, s in pairs if s is not None)
    t.check("the standby's readings are no more than 50 ms older than the primary's, read at "
            "the same moment (30 pairs, at most %s ms)" % max(behind, default=None),
            len(behind) == 30 and max(behind) <= (250 if SANITIZED else 50), pairs)
    t.check("and within the poll period plus 50 ms (the median of 30 reads, %s ms)"
            % (ages[len(ages) // 2] if ages else None),
            len(ages) == 30 and ages[len(ages) // 2] <= POLL_MS + 50, ages)
    d = plc.client.read_discrete_inputs(8, 1, slave=1)
    t.check("the standby's discrete input 8 (standby) is on", not d.isError() and d.bits[0], d)
    d = plc_primary.client.read_discrete_inputs(8, 1, slave=1)
    t.check("the primary's discrete input 8 is off", not d.isError() and not d.bits[0], d)
    w = plc.client.write_register(0, 3, slave=1)  # filter 3
    t.check("a write on the standby is refused with 0x0A",
            w.isError() and getattr(w, "exception_code", None) == 0x0A, w)
    t.check("the standby sent nothing on the line while the primary ran",
            sim.sent(1) == 0, sim.stats())
    standby.process.send_signal(signal.SIGHUP)
    time.sleep(1.0)
    t.check("a reload of the standby keeps it listening, warm, sending nothing",
            role(standby) == "standby" and sim.sent(1) == 0
            and (lambda g: g is not None and g.online)(plc.read(2)),
            (status(standby), sim.stats()))

    # SIGSTOP the primary for longer than takeover_ms: the standby takes the line. The PLC
    # reads through the standby all along.
    before = sim.sent(1)
    os.kill(primary.process.pid, signal.SIGSTOP)
    stopped_at = time.monotonic()
    ages, primary_sent, took_s = [], None, None
    while time.monotonic() < stopped_at + (TAKEOVER_MS + POLL_MS) / 1000 + SLACK_S + 0.5:
        ages.append(age_of(plc, 1))
        since = time.monotonic() - stopped_at
        if primary_sent is None and since > 0.3:  # the counts file is rewritten every 100 ms
            primary_sent = sim.sent(0)
        if took_s is None and role(standby) == "active":
            took_s = since
        time.sleep(0.04)
    t.check("with the primary stopped, the standby takes the line (%s s after SIGSTOP)"
            % (None if took_s is None else round(took_s, 2)),
            took_s is not None, (status(standby), standby.log()))
    t.check("the standby's first requests go out", wait_until(lambda: sim.sent(1) > before, 5),
            sim.stats())
    t.check("the standby's first request within takeover_ms + a poll period of the primary's "
            "last, give or take this test's own polling",
            took_s is not None and took_s <= (TAKEOVER_MS + POLL_MS) / 1000 + SLACK_S, took_s)
    t.check("the primary sent nothing while stopped", sim.sent(0) == primary_sent, sim.stats())
    t.check("the PLC reading through the standby never saw a reading older than takeover_ms + "
            "2 poll periods (the oldest %s ms)" % max(ages, key=lambda a: a or 0),
            None not in ages and max(ages) <= TAKEOVER_MS + 2 * POLL_MS + 1000 * (SLACK_S - 0.3),
            ages)
    t.check("the standby's status bit 7 is clear once it is active",
            wait_until(lambda: (lambda r: not r.isError() and r.registers[0] & 0x80 == 0)(
                plc.client.read_input_registers(6, 1, slave=1)), 3))

    # SIGCONT: the old primary was held up: it stands down, and never fights.
    os.kill(primary.process.pid, signal.SIGCONT)
    t.check("the old primary stands down after SIGCONT",
            wait_until(lambda: role(primary) == "standby", 10), (status(primary), primary.log()))
    sent_after = sim.sent(0)
    time.sleep(1.0)
    t.check("the old primary then sends nothing", sim.sent(0) == sent_after, sim.stats())
    t.check("it serves warm from what it hears",
            wait_until(lambda: (lambda g: g is not None and g.online)(plc_primary.read(1)), 5))

    # SIGKILL the active one (the former standby): the former primary takes the line again.
    plc.close()
    os.kill(standby.process.pid, signal.SIGKILL)
    killed_at = time.monotonic()
    t.check("with the active gateway killed, the other takes the line",
            wait_until(lambda: role(primary) == "active", 10), (status(primary), primary.log()))
    t.check("takeover after SIGKILL within takeover_ms (%.2f s)"
            % (time.monotonic() - killed_at),
            time.monotonic() - killed_at <= TAKEOVER_MS / 1000 + SLACK_S)
    t.check("readings fresh through it again",
            wait_until(lambda: (lambda g: g is not None and g.online)(plc_primary.read(2)), 5))
    # A reload of the active gateway keeps it active; one that changes [redundancy] is refused.
    takeovers = status(primary)["redundancy"]["takeovers"]
    primary.process.send_signal(signal.SIGHUP)
    time.sleep(1.0)
    t.check("after a reload the gateway is still the active one, with no new takeover",
            role(primary) == "active" and status(primary)["redundancy"]["takeovers"] == takeovers,
            status(primary))
    t.check("readings stay fresh across the reload",
            wait_until(lambda: (lambda g: g is not None and g.online)(plc_primary.read(1)), 3))
    with open(primary.config_path) as f:
        text = f.read()
    with open(primary.config_path, "w") as f:
        f.write(text.replace("takeover_ms = %d" % TAKEOVER_MS, "takeover_ms = %d" % (TAKEOVER_MS + 1000)))
    primary.process.send_signal(signal.SIGHUP)
    t.check("a reload that changes [redundancy] is refused, the gateway serving on",
            wait_until(lambda: "read only at start" in primary.log(20000), 5)
            and role(primary) == "active", primary.log())
    t.check("no collision on the line in the whole test", sim.stats().get("collisions") == 0,
            sim.stats())
    plc_primary.close()
    t.check("the gateway stops cleanly", primary.stop() == 0)


if __name__ == "__main__":
    sys.exit(Checks("warm-standby").run(scenario))
