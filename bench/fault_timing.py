#!/usr/bin/env python3
"""What a PLC sees, and how soon, when sensors on a shared line fail, with every bus and sensor
timing key at its default (`poll_ms` 100, `timeout_ms` 50, `retries` 2, `max_timeout_ms` 500,
so `late_guard_ms` 450, `stale_ms` 1000): the times behind docs/operations.md, "What the PLC
sees when something fails" and "One failing sensor never takes its line".

H6 sensors at addresses 1..N on `tiltgate sim rieker` (paced at the bus's baud), polled by
`tiltgate run` with writes on; faults come from the simulator's standard input (`silent`,
`garbage`, `late`, `busy`, `answer`), the tty's loss from stopping the simulator.

1. Detection: sensor 3 of six at 125000 baud falls silent; when a PLC reading it back to back
   (status word, then angle_x) first sees status bit 0 clear and the angles answer 0x0B; after
   3 s of silence it answers again: when bit 0 sets and the angles are back. Times from the
   simulator's "ok", so they include the part of a poll period since the last good reading.
   Medians and the longest over the rounds.
2. Neighbours: for each fault, six H6 at 125000 baud and ten at 9600, a PLC reads every healthy
   unit's status, age (input register 7) and angle every 30 ms for 8 s from the fault: the
   oldest any of their readings got (each reading's time is the read's less its age; the
   longest gap between two readings in a row), and how many reads found one stale, offline or
   its angle 0x0B. "written" also writes sensor 3's filter (it is silent) and a healthy
   neighbour's once a second: both writes' answer times, median and longest, and what they
   answered. The tty row stops the simulator for 3 s: from its return until the gateway's
   reopen (its back-off) and from the reopen until every sensor read fresh.

Usage: bench/fault_timing.py [--rounds N] [--seconds S] [--build DIR]
"""
import argparse
import datetime
import os
import re
import socket
import statistics
import struct
import sys
import tempfile
import threading
import time

from bus_gateway import Gateway, start_simulator, stop
from modbus_tcp_client import modbus_call, read_input

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SILENCE_S = 3.0
SICK, SECOND_SICK, NEIGHBOUR = 3, 5, 4


def connect(port):
    connection = socket.create_connection(("127.0.0.1", port))
    connection.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return connection


def status_word(connection, unit=SICK):
    (word,) = read_input(connection, unit, 6, 1)
    return word


def angles_unavailable(connection, unit=SICK):
    try:
        read_input(connection, unit, 0, 2)
        return False
    except ValueError as e:
        if "0B" not in str(e):
            sys.exit(f"unexpected reply to the angles: {e}")
        return True


def watch(connection, since, until, limit_s=10):
    """Reads status and angles back to back until both show `until`; returns when the status
    first said online == wanted and when the angles first said unavailable == wanted, in ms
    after `since`."""
    status_at = angles_at = None
    while status_at is None or angles_at is None:
        if time.monotonic() - since > limit_s:
            sys.exit("the gateway never showed the change")
        online = bool(status_word(connection) & 0x01)
        now = time.monotonic()
        if status_at is None and until["online"] == online:
            status_at = (now - since) * 1000
        unavailable = angles_unavailable(connection)
        now = time.monotonic()
        if angles_at is None and until["unavailable"] == unavailable:
            angles_at = (now - since) * 1000
    return status_at, angles_at


def detection(binary, folder, rounds):
    gateway = Gateway(binary, folder, 125000, 1, 6, None, commands=True)
    offline, unavailable, online_again, fresh_again = [], [], [], []
    try:
        gateway.wait_all_polled()
        with connect(gateway.modbus_port) as connection:
            for r in range(rounds):
                time.sleep(1.0 + 0.1 * ((r * 7919) % 10) / 10)
                gateway.sim_command(f"silent {SICK}")
                silent = time.monotonic()
                bit0, exception = watch(connection, silent, {"online": False, "unavailable": True})
                offline.append(bit0)
                unavailable.append(exception)
                time.sleep(max(0.0, SILENCE_S - (time.monotonic() - silent)))
                gateway.sim_command(f"answer {SICK}")
                answering = time.monotonic()
                bit0, fresh = watch(connection, answering, {"online": True, "unavailable": False})
                online_again.append(bit0)
                fresh_again.append(fresh)
    finally:
        gateway.stop()

    def cells(values):
        return f"{statistics.median(values):.0f} | {max(values):.0f}"

    print(f"1. A sensor (3 of six H6, 125000 baud) falls silent and answers again, defaults, "
          f"{rounds} rounds, ms after the simulator's ok")
    print()
    print("| event | median | longest |")
    print("| --- | ---: | ---: |")
    print(f"| silent: status bit 0 clears | {cells(offline)} |")
    print(f"| silent: the angles answer 0x0B | {cells(unavailable)} |")
    lead = [u - o for o, u in zip(offline, unavailable)]
    print(f"| silent: bit 0 before 0x0B by (negative: after) | {round(statistics.median(lead))} | "
          f"{round(min(lead))} (least) |")
    print(f"| answers again after {SILENCE_S:.0f} s: bit 0 sets | {cells(online_again)} |")
    print(f"| answers again: fresh angles | {cells(fresh_again)} |")
    print()


class Plc(threading.Thread):
    """Reads every unit of `units`: status and age (input registers 6, 7), then angle_x, one
    cycle every 30 ms, and keeps what a PLC would have seen go wrong."""

    def __init__(self, port, units):
        super().__init__(daemon=True)
        self.port, self.units = port, units
        self.running = True
        self.worst_age = 0
        self.stale = self.offline = self.unavailable = 0
        self.last_taken = {}
        self.fresh_at = {}  # each unit's first fresh read after mark()
        self.mark_at = None

    def mark(self):
        self.fresh_at = {}
        self.mark_at = time.monotonic()

    def reset(self):
        """From now on: what came before the fault (the gateway's start) does not count. The
        readings taken before stay, so a reading that has to wait through the fault counts."""
        self.worst_age = 0
        self.stale = self.offline = self.unavailable = 0

    def run(self):
        with connect(self.port) as connection:
            while self.running:
                start = time.monotonic()
                for unit in self.units:
                    self.read(connection, unit)
                time.sleep(max(0.0, 0.03 - (time.monotonic() - start)))

    def read(self, connection, unit):
        status, age = read_input(connection, unit, 6, 2)
        read_at = time.monotonic()
        try:
            read_input(connection, unit, 0, 2)
            readable = True
        except ValueError:
            readable = False
            self.unavailable += 1
        online, stale = status & 1, status & 2
        self.offline += 0 if online else 1
        self.stale += 1 if stale else 0
        if age == 65535:
            return
        taken = read_at - age / 1000
        last = self.last_taken.get(unit)
        if last is not None and taken - last > 0.005:
            self.worst_age = max(self.worst_age, (taken - last) * 1000)
        if last is None or taken > last:
            self.last_taken[unit] = taken
        self.worst_age = max(self.worst_age, age)
        if (self.mark_at is not None and online and not stale and readable
                and taken > self.mark_at and unit not in self.fresh_at):
            self.fresh_at[unit] = read_at


def write_filter(connection, unit, value):
    """Function 06 to holding register 0: the answer's time in ms and its exception (0: done)."""
    sent = time.monotonic()
    reply = modbus_call(connection, unit, struct.pack(">BHH", 6, 0, value))
    took = (time.monotonic() - sent) * 1000
    return took, reply[1] if reply[0] & 0x80 else 0


def log_time(line):
    """The time of a log line of the gateway's, as time.time() would have said."""
    stamp = datetime.datetime.strptime(line[:23], "%Y-%m-%d %H:%M:%S.%f")
    return stamp.timestamp()


def one_fault(binary, folder, baud, count, fault, seconds):
    """Runs `fault` on a fresh line; returns the PLC's findings and the fault's own figures."""
    gateway = Gateway(binary, tempfile.mkdtemp(dir=folder), baud, 1, count, None, commands=True,
                      server_keys="writes = true")
    sick = {"two silent": [SICK, SECOND_SICK], "tty": []}.get(fault, [SICK])
    plc = Plc(gateway.modbus_port, [u for u in range(1, count + 1) if u not in sick])
    extra = {}
    try:
        gateway.wait_all_polled()
        plc.start()
        time.sleep(2.0)
        plc.reset()
        if fault == "tty":
            extra = tty_loss(binary, gateway, baud, count, plc)
        else:
            commands = {"silent": ["silent 3"], "garbage": ["garbage 3"], "late": ["late 3 300"],
                        "busy": ["busy 3"], "written": ["silent 3"],
                        "two silent": ["silent 3", "silent 5"]}[fault]
            for command in commands:
                gateway.sim_command(command)
            if fault == "written":
                extra = write_each_second(gateway.modbus_port, seconds)
            else:
                time.sleep(seconds)
    finally:
        plc.running = False
        plc.join(5)
        gateway.stop()
    return plc, extra


def write_each_second(port, seconds):
    to_sick, to_neighbour = [], []
    with connect(port) as connection:
        for s in range(int(seconds)):
            start = time.monotonic()
            to_sick.append(write_filter(connection, SICK, 2 + s % 3))
            to_neighbour.append(write_filter(connection, NEIGHBOUR, 2 + s % 3))
            time.sleep(max(0.0, 1.0 - (time.monotonic() - start)))
    return {"sick": to_sick, "neighbour": to_neighbour}


def tty_loss(binary, gateway, baud, count, plc):
    """Stops the simulator for 3 s and starts a new one on the same link."""
    link = os.path.join(os.path.dirname(gateway.log_path), "tty0")
    stop(gateway.sims[0])
    time.sleep(SILENCE_S)
    back = time.time()
    plc.mark()
    gateway.sims[0] = start_simulator(binary, link, baud, count, commands=True)
    end = time.monotonic() + 20
    reopened = None
    while time.monotonic() < end and len(plc.fresh_at) < len(plc.units):
        time.sleep(0.05)
        if reopened is None:
            gateway.log.flush()
            with open(gateway.log_path) as f:
                lines = [line for line in f if "reopened" in line]
            if lines:
                reopened = log_time(lines[-1])
    if reopened is None or len(plc.fresh_at) < len(plc.units):
        sys.exit("the sensors never read fresh after the tty came back")
    fresh = max(plc.fresh_at.values())  # monotonic; the reopen's wall time made monotonic:
    reopened_monotonic = time.monotonic() - (time.time() - reopened)
    return {"reopen_after": (reopened - back) * 1000,
            "fresh_after_reopen": (fresh - reopened_monotonic) * 1000}


def neighbours(binary, folder, seconds):
    faults = ["silent", "garbage", "late", "busy", "written", "two silent", "tty"]
    names = {"silent": "sensor 3 silent", "garbage": "sensor 3 answers a broken CRC",
             "late": "sensor 3 answers 300 ms late", "busy": "sensor 3 answers NAK 5 (busy)",
             "written": "sensor 3 silent, its filter and a neighbour's written each second",
             "two silent": "sensors 3 and 5 fall silent at once",
             "tty": "the tty gone for 3 s"}
    print(f"2. What a fault costs the healthy sensors on its line: {seconds:g} s from the fault, "
          f"a PLC reading each healthy unit every 30 ms; stale_ms 1000")
    print()
    print("| line | fault | neighbours' oldest reading, ms | reads stale / offline / 0x0B | "
          "writes |")
    print("| --- | --- | ---: | ---: | --- |")
    for baud, count in ((125000, 6), (9600, 10)):
        for fault in faults:
            plc, extra = one_fault(binary, folder, baud, count, fault, seconds)
            writes = "-"
            if fault == "written":
                def times(answers):
                    took = [t for t, _ in answers]
                    codes = sorted({f"{e:02X}" if e else "ok" for _, e in answers})
                    return (f"{statistics.median(took):.0f} / {max(took):.0f} ms, "
                            f"{' '.join(codes)}")
                writes = (f"to sensor 3: {times(extra['sick'])}; to sensor {NEIGHBOUR}: "
                          f"{times(extra['neighbour'])}")
            elif fault == "tty":
                writes = (f"reopened {extra['reopen_after']:.0f} ms after the tty returned; "
                          f"every sensor fresh {extra['fresh_after_reopen']:.0f} ms after the "
                          f"reopen")
            # With the tty gone every sensor is lost: its row is about the return.
            seen = ("- | -" if fault == "tty" else
                    f"{plc.worst_age:.0f} | {plc.stale} / {plc.offline} / {plc.unavailable}")
            print(f"| {count} x H6, {baud} baud | {names[fault]} | {seen} | {writes} |")
    print()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--seconds", type=float, default=8)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    args = parser.parse_args()
    binary = os.path.join(args.build, "tiltgate")
    folder = tempfile.mkdtemp(prefix="tiltgate-fault-timing-")
    detection(binary, tempfile.mkdtemp(dir=folder), args.rounds)
    neighbours(binary, folder, args.seconds)


if __name__ == "__main__":
    main()
