#!/usr/bin/env python3
"""What a PLC sees, and how soon, when a sensor falls silent and answers again, with every bus and
sensor setting at its default (`poll_ms` 100, `timeout_ms` 50, `retries` 2, `max_timeout_ms`
500, so `late_guard_ms` 450, `stale_ms` 1000): the times behind the table of
docs/operations.md, "What the PLC sees when something fails".

One H6 on `tiltgate sim rieker` (125000 baud, paced), polled by `tiltgate run`. Each round waits a
random part of a poll period, tells the simulator `silent 1` on its standard input (timed from
its "ok"), and reads unit 1 back to back over Modbus TCP, status word (input register 6) then
angle_x (input registers 0-1), until the status says offline and the angles answer 0x0B; after
3 s of silence it says `answer 1` and reads until the status says online and the angles are
back. Times are from the simulator's "ok", in ms, so they include the part of a poll period
since the sensor's last good reading (0-100 ms). Medians and the longest over the rounds.

Usage: bench/fault_timing.py [--rounds N] [--build DIR]
"""
import argparse
import os
import random
import socket
import statistics
import sys
import tempfile
import time

from bus_gateway import Gateway
from modbus_tcp_client import read_input

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SILENCE_S = 3.0


def status_word(connection):
    (word,) = read_input(connection, 1, 6, 1)
    return word


def angles_unavailable(connection):
    try:
        read_input(connection, 1, 0, 2)
        return False
    except ValueError as e:
        if "0B" not in str(e):
            sys.exit(f"unexpected reply to the angles: {e}")
        return True


def watch(connection, since, until, limit_s=10):
    """Reads status and angles back to back until until(online, unavailable) holds for both
    seen at once; returns when the status first said online == wanted and when the angles
    first said unavailable == wanted, in ms after `since`."""
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


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    args = parser.parse_args()
    binary = os.path.join(args.build, "tiltgate")
    folder = tempfile.mkdtemp(prefix="tiltgate-fault-timing-")
    gateway = Gateway(binary, folder, 125000, 1, 1, 100, commands=True)
    chance = random.Random(7)
    offline, unavailable, online_again, fresh_again = [], [], [], []
    try:
        gateway.wait_all_polled()
        with socket.create_connection(("127.0.0.1", gateway.modbus_port)) as connection:
            connection.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            for _ in range(args.rounds):
                time.sleep(1.0 + chance.uniform(0, 0.1))
                gateway.sim_command("silent 1")
                silent = time.monotonic()
                bit0, exception = watch(connection, silent, {"online": False, "unavailable": True})
                offline.append(bit0)
                unavailable.append(exception)
                time.sleep(max(0.0, SILENCE_S - (time.monotonic() - silent)))
                gateway.sim_command("answer 1")
                answering = time.monotonic()
                bit0, fresh = watch(connection, answering, {"online": True, "unavailable": False})
                online_again.append(bit0)
                fresh_again.append(fresh)
    finally:
        gateway.stop()

    def cells(values):
        return f"{statistics.median(values):.0f} | {max(values):.0f}"

    print(f"A sensor falls silent and answers again, defaults, {args.rounds} rounds, ms after "
          f"the simulator's ok")
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


if __name__ == "__main__":
    main()
