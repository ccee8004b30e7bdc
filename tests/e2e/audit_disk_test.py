#!/usr/bin/env python3
"""The audit trail on a disk that refuses it, and its tamper evidence, end to end (issue 52,
items 2 and 4), with build/tiltgate, `tiltgate sim rieker` and the trail's state_dir on a
64 KiB tmpfs of the test's own, filled to ENOSPC:

- Modbus writes acknowledged while the disk is full, and more once it has room again: every
  one is in `tiltgate audit` once the disk takes the trail, and on disk after SIGTERM.
- one made while the disk is full at SIGTERM: the log says at error that it is lost.
- [audit] memory_kib = 16: past the budget records are lost, counted in
  tiltgate_audit_records_lost_total, said at error, and the trail says so itself afterwards.
- [audit] when_full = "refuse": while the disk refuses, a write is refused (exception 04),
  and so is a `tiltgate raw --via-gateway` that would change a sensor (a read goes through);
  both are taken again once the disk has room.
- `tiltgate audit --verify` exits 0 on the trails above, and 1 naming the record once one
  record was edited (its frame's CRC made right again, as a hostile hand would).

Runs in a mount namespace of its own (unshare -m), so no mount outlives it; needs root, as CI
runs (exit 77, skipped, otherwise).

Usage: /usr/bin/python3 audit_disk_test.py path/to/tiltgate
"""
import json
import os
import socket
import struct
import subprocess
import sys
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from small_disk import SmallDisk, run_in_own_mount_namespace  # noqa: E402

run_in_own_mount_namespace()
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sparkplug"))
from spb_e2e import store_files  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e.plant import Gateway, Simulator  # noqa: E402
from spb_e2e.processes import wait_until  # noqa: E402

WAIT = 20


def modbus_write(port, value, register=0, unit=1):
    """FC 6 to the gateway: "ok", or "exception N"."""
    with socket.create_connection(("127.0.0.1", port), timeout=15) as s:
        s.sendall(struct.pack(">HHHBBHH", 7, 0, 6, unit, 6, register, value))
        reply = s.recv(260)
    if len(reply) >= 9 and reply[7] == 0x86:
        return "exception %d" % reply[8]
    return "ok" if len(reply) >= 12 and reply[7] == 6 else "reply %r" % reply


def audit(tiltgate, state_dir, *args):
    return subprocess.run([tiltgate, "audit", "--state-dir", state_dir] + list(args),
                          capture_output=True, text=True, timeout=30)


def records(tiltgate, state_dir):
    done = audit(tiltgate, state_dir, "--json", "--limit", "0")
    return json.loads(done.stdout) if done.returncode == 0 else []


def raw_via_gateway(tiltgate, gateway, sim, function, data=None):
    """`tiltgate raw --via-gateway` to the H6 at 223 through the gateway's control socket."""
    command = [tiltgate, "raw", "--via-gateway", "--control-socket", gateway.control_socket,
               "--port", sim.link, "--protocol", "rieker", "--address", "223",
               "--function", str(function)]
    if data is not None:
        command += ["--data", data]
    return subprocess.run(command, capture_output=True, text=True, timeout=30)


def audit_metrics(gateway):
    """What a failed check shows: the trail's series of /metrics and the writes' exceptions."""
    return {k: v for k, v in gateway.metrics().items()
            if k.startswith("tiltgate_audit") or k.startswith("tiltgate_modbus_exceptions")}


def gateway_on(t, tiltgate, sim, state_dir, name, audit_keys=""):
    gateway = Gateway(tiltgate, t.dir, sim, None, name=name)
    gateway.control_socket = os.path.join(t.dir, name + ".sock")
    with open(gateway.config_path) as f:
        text = f.read()
    text = text.replace("[server]\n", '[server]\nwrites = true\nstate_dir = "%s"\n' % state_dir, 1)
    text = text.replace('control_socket = ""', 'control_socket = "%s"' % gateway.control_socket)
    if audit_keys:
        text += "\n[audit]\n" + audit_keys + "\n"
    with open(gateway.config_path, "w") as f:
        f.write(text)
    t.logs.append((name, gateway.log_path))
    gateway.start()
    return gateway


def writes_on_a_full_disk(t, tiltgate, sim, disk):
    state_dir = os.path.join(disk.path, "state")
    gateway = gateway_on(t, tiltgate, sim, state_dir, "full-gw")
    disk.fill()
    answers = [modbus_write(gateway.modbus_port, v) for v in (2, 3)]
    t.check("two Modbus writes on the full disk are acknowledged", answers == ["ok", "ok"],
            answers)
    t.check("and held for the disk: tiltgate_audit_records_held 2, the disk refuses",
            wait_until(lambda: gateway.metric("tiltgate_audit_records_held") == 2 and
                       gateway.metric("tiltgate_audit_disk_refuses") == 1, WAIT),
            audit_metrics(gateway))
    disk.free()
    answers = [modbus_write(gateway.modbus_port, v) for v in (2, 3)]
    t.check("two more once the filler is gone", answers == ["ok", "ok"], answers)
    modbus = lambda: [r for r in records(tiltgate, state_dir) if r["door"] == "modbus"]
    t.check("all four are in `tiltgate audit` while the gateway runs",
            wait_until(lambda: len(modbus()) == 4, WAIT), modbus())
    t.check("nothing was lost: tiltgate_audit_records_lost_total 0",
            gateway.metric("tiltgate_audit_records_lost_total") == 0, audit_metrics(gateway))
    disk.fill()
    # The segment's last page may still take a few records: write until one is held.
    written = 0
    while written < 60 and not gateway.metric("tiltgate_audit_records_held", 0):
        modbus_write(gateway.modbus_port, 2 + written % 2)
        written += 1
        wait_until(lambda: gateway.metric("tiltgate_audit_records_held", 0) > 0, 1)
    t.check("on a full disk again a write's record is held",
            gateway.metric("tiltgate_audit_records_held") == 1, audit_metrics(gateway))
    gateway.stop()
    t.check("after SIGTERM the others are on disk", len(modbus()) == 4 + written - 1,
            (written, modbus()))
    t.check("and the one the full disk still refused at the stop is said lost, at error",
            "1 records held in memory are lost as the gateway stops" in gateway.log(),
            gateway.log()[-800:])
    disk.free()
    verified = audit(tiltgate, state_dir, "--verify")
    t.check("`tiltgate audit --verify` finds the chain whole: exit 0", verified.returncode == 0,
            verified.stdout + verified.stderr)
    return state_dir


def past_the_memory_budget(t, tiltgate, sim, disk):
    state_dir = os.path.join(disk.path, "budget")
    gateway = gateway_on(t, tiltgate, sim, state_dir, "budget-gw", "memory_kib = 16")
    disk.fill()
    for i in range(200):
        if gateway.metric("tiltgate_audit_records_lost_total", 0) > 0:
            break
        modbus_write(gateway.modbus_port, 2 + i % 2)
    lost = gateway.metric("tiltgate_audit_records_lost_total", 0)
    t.check("past memory_kib records are lost and counted in tiltgate_audit_records_lost_total",
            lost > 0, audit_metrics(gateway))
    t.check("said at error in the log",
            "records are lost from now on until the disk takes the trail again" in
            gateway.log(), gateway.log()[-800:])
    disk.free()
    notice = lambda: [r for r in records(tiltgate, state_dir) if r["setting"] == "records lost"]
    t.check("once the disk has room the trail says how many were lost",
            wait_until(lambda: len(notice()) == 1, WAIT) and
            notice()[0]["new"] == str(int(gateway.metric("tiltgate_audit_records_lost_total"))),
            notice())
    gateway.stop()
    verified = audit(tiltgate, state_dir, "--verify")
    t.check("the chain holds over the gap, with the record that names it",
            verified.returncode == 0, verified.stdout + verified.stderr)


def refused_when_full(t, tiltgate, sim, disk):
    state_dir = os.path.join(disk.path, "refuse")
    gateway = gateway_on(t, tiltgate, sim, state_dir, "refuse-gw", 'when_full = "refuse"')
    t.check("with when_full refuse a write on a disk with room is carried out",
            modbus_write(gateway.modbus_port, 2) == "ok")
    disk.fill()
    # The segment's last page may still take a few records: write until the disk refuses.
    for i in range(60):
        if gateway.metric("tiltgate_audit_disk_refuses") == 1:
            break
        modbus_write(gateway.modbus_port, 2 + i % 2)
        wait_until(lambda: gateway.metric("tiltgate_audit_disk_refuses") == 1, 1)
    t.check("the trail finds its disk refusing",
            gateway.metric("tiltgate_audit_disk_refuses") == 1, audit_metrics(gateway))
    answer = modbus_write(gateway.modbus_port, 2)
    t.check("a write is then refused with exception 04", answer == "exception 4", answer)
    raw = raw_via_gateway(tiltgate, gateway, sim, 41, "02")
    t.check("and so is a raw Set Filter through the control socket, saying why",
            raw.returncode != 0 and "audit trail" in raw.stderr, raw.stdout + raw.stderr)
    raw = raw_via_gateway(tiltgate, gateway, sim, 37)
    t.check("while a raw Get Serial, which changes nothing, is answered",
            raw.returncode == 0 and "serial" in raw.stdout,
            raw.stdout + raw.stderr)
    disk.free()
    t.check("once the disk has room again",
            wait_until(lambda: gateway.metric("tiltgate_audit_disk_refuses") == 0, WAIT),
            audit_metrics(gateway))
    answer = modbus_write(gateway.modbus_port, 3)
    t.check("writes are carried out again", answer == "ok", answer)
    refused = lambda: [r for r in records(tiltgate, state_dir)
                       if r["result"].startswith("refused: the audit trail's disk")]
    raw_refused = lambda: [r for r in refused() if r["setting"].startswith("function 41")]
    # The loop above may have met the refusal with one write more: at least one refused write.
    t.check("and the refused write and raw request are in the trail with their reason",
            wait_until(lambda: len(raw_refused()) == 1 and len(refused()) >= 2, WAIT),
            records(tiltgate, state_dir))
    gateway.stop()


def an_edited_record(t, tiltgate, state_dir):
    segment = store_files.segments(os.path.join(state_dir, "audit"))[0]
    frames = store_files.frames(segment)
    victim = frames[1]
    body = json.loads(victim.payload)
    body["new"] = "9"
    payload = json.dumps(body, separators=(",", ":")).encode()
    with open(segment, "rb") as f:
        data = f.read()
    topic = victim.topic.encode()
    body_bytes = struct.pack("<BBHq", 1, 0, len(topic), victim.time_ms) + topic + payload
    length = struct.pack("<I", len(body_bytes))
    frame = length + struct.pack("<I", zlib.crc32(length + body_bytes)) + body_bytes
    with open(segment, "wb") as f:
        f.write(data[:victim.offset] + frame + data[victim.offset + victim.size:])
    shown = audit(tiltgate, state_dir, "--limit", "0")
    t.check("`tiltgate audit` reads the edited trail (the frame is whole)",
            shown.returncode == 0 and "-> 9" in shown.stdout, shown.stdout + shown.stderr)
    verified = audit(tiltgate, state_dir, "--verify")
    t.check("`tiltgate audit --verify` exits 1 naming the record after the edited one",
            verified.returncode == 1 and "record 3: its prev does not match" in verified.stdout
            and "record 2: that record was edited" in verified.stdout,
            verified.stdout + verified.stderr)


def scenario(t):
    tiltgate, _ = arguments()
    disk = SmallDisk(os.path.join(t.dir, "disk"), 64)
    try:
        sim = Simulator(tiltgate, t.dir)
        t.logs.append(("simulator", sim.err_path))
        state_dir = writes_on_a_full_disk(t, tiltgate, sim, disk)
        an_edited_record(t, tiltgate, state_dir)
        past_the_memory_budget(t, tiltgate, sim, disk)
        refused_when_full(t, tiltgate, sim, disk)
    finally:
        disk.unmount()


if __name__ == "__main__":
    sys.exit(Checks("audit-disk").run(scenario))
