#!/usr/bin/env python3
"""What a triggered burst costs a line (issue 57, item 8; docs/monitoring.md, "Bursts"):
`tiltgate run` polling 10 simulated Rieker H6 at 125000 baud, the first with burst_s and an
alarm; a step past the alarm starts its burst. For a line with room to spare (poll_ms = 100,
1000 polls/s asked of a wire that takes about 460) and a full one (poll_ms = 20), the polls/s of
the bursting sensor and of its nine neighbours, before and during the burst: medians of 3
rounds, each a fresh gateway. The neighbours keep their period where the line has room; on a
full line the burst takes what the line has left, and the neighbours' ratio says what it took.

Usage: bench/bursts.py [--rounds N] [--seconds S] [--build DIR]
"""
import argparse
import os
import statistics
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bus_gateway import Gateway, rates  # noqa: E402

BAUD = 125000
SENSORS = 10


def round_(binary, poll_ms, seconds):
    """One fresh gateway: the first sensor's and the neighbours' median polls/s, before the
    trigger and during the burst."""
    with tempfile.TemporaryDirectory(prefix="tiltgate-bench-bursts-") as folder:
        keys = (f"burst_s = {int(seconds * 3)}\npre_trigger_s = 1\n"
                "alarms = { x_high = 10.0, hysteresis_deg = 1.0 }")
        gateway = Gateway(binary, folder, BAUD, 1, SENSORS, poll_ms, commands=True,
                          first_sensor_keys=keys)
        try:
            gateway.sim_command("angle 1 0.0 0.0")
            gateway.wait_all_polled()
            time.sleep(0.5)
            before = gateway.polls()
            time.sleep(seconds)
            idle = rates(before, gateway.polls())
            gateway.sim_command("angle 1 20.0 0.0")  # past x_high: the burst starts
            time.sleep(0.5)
            before = gateway.polls()
            time.sleep(seconds)
            burst = rates(before, gateway.polls())
        finally:
            gateway.stop()
    first = "s0_1"
    neighbours = lambda r: statistics.median(v for k, v in r.items() if k != first)
    return idle[first], neighbours(idle), burst[first], neighbours(burst)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--build", default=os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "build"))
    args = parser.parse_args()
    binary = os.path.join(args.build, "tiltgate")
    print(f"Bursts on one line: {SENSORS} H6 at {BAUD} baud, the first bursting; polls/s, "
          f"medians of {args.rounds} rounds of {args.seconds:g} s before and during the burst\n")
    print("| poll_ms | asked (polls/s) | bursting sensor before | during | neighbour before | "
          "during | neighbours during / before | line before | during |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for poll_ms in (100, 20):
        rows = [round_(binary, poll_ms, args.seconds) for _ in range(args.rounds)]
        med = [statistics.median(r[i] for r in rows) for i in range(4)]
        line_before = med[0] + (SENSORS - 1) * med[1]
        line_during = med[2] + (SENSORS - 1) * med[3]
        print(f"| {poll_ms} | {SENSORS * 1000 / poll_ms:.0f} | {med[0]:.1f} | {med[2]:.1f} | "
              f"{med[1]:.1f} | {med[3]:.1f} | {med[3] / med[1]:.3f} | {line_before:.0f} | "
              f"{line_during:.0f} |")


if __name__ == "__main__":
    main()
