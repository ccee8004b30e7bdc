#!/usr/bin/env python3
"""See the wire (issue 55, items 3, 5 and 8; docs/diagnostics.md, "Capture for Wireshark"):
build/tiltgate runs a Rieker bus and a Modbus RTU bus on simulators, and `tiltgate capture`
takes their frames through its control socket. Debian's tshark reads the files: Wireshark's
own Modbus RTU dissector finds every CRC good; the project's Lua dissector names the Rieker
functions, and flags the replies whose CRC the simulator broke, which the gateway's verdict
also calls "no reply: bad CRC"; the black box (--last) holds what came before the sensor was
said to stop answering, as the log says. Each capture is recorded in the audit trail; bad
command lines and a missing gateway get a clear error.

Usage: /usr/bin/python3 capture_e2e_test.py path/to/tiltgate
"""
import json
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
import spb_path  # noqa: F401,E402
from network_plant import RTU_PROFILE, Gateway, Simulator, bus  # noqa: E402
from spb_e2e.checks import Checks, arguments  # noqa: E402
from spb_e2e import processes  # noqa: E402
from spb_e2e.processes import free_port, wait_until  # noqa: E402
from tshark_fields import LUA, tshark_fields  # noqa: E402

def read_capture(t, path, fields, display_filter=None):
    """Each packet's fields, Modbus RTU CRCs checked (Wireshark's mbrtu leaves them unchecked)."""
    return tshark_fields(path, fields, t.dir, extra=("-o", "mbrtu.crc_verification:TRUE"),
                         display_filter=display_filter)


def capture(t, tiltgate, config, *args, timeout=60):
    argv = [tiltgate, "capture", "--config", config] + list(args)
    return subprocess.run(argv, capture_output=True, timeout=timeout)


def scenario(t):
    tiltgate, _ = arguments()
    if not shutil.which("tshark"):
        t.check("tshark is installed (Debian package tshark; run scripts/setup)", False)
        return
    rieker = Simulator(tiltgate, t.dir, "rieker", "h6:223,h4360:101", name="rieker")
    rtu = Simulator(tiltgate, t.dir, "modbus-rtu", "modbus-rtu:5", baud=38400, name="rtu")
    t.logs += [("rieker simulator", rieker.err_path), ("rtu simulator", rtu.err_path)]
    # A Modbus TCP device: the demo's unit 5 (a Modbus RTU device behind it), on a free port.
    demo_port = free_port()
    demo_log = os.path.join(t.dir, "demo.log")
    t.logs.append(("demo", demo_log))
    processes.start([tiltgate, "demo", "--port", str(demo_port), "--http-port", "0",
                     "--no-accounts", "--control-socket", os.path.join(t.dir, "demo.sock")],
                    stdout=open(demo_log, "w"), stderr=subprocess.STDOUT)
    gateway = Gateway(tiltgate, t.dir, [
        bus("line1", rieker.link, "rieker", [("boom", "h6", 223, 1, {"poll_ms": 100}),
                                             ("mast", "h4360", 101, 2, {"poll_ms": 100})],
            black_box_s=30),
        bus("rtu1", rtu.link, "modbus-rtu",
            [("tilt", "modbus-rtu", 5, 3, {"poll_ms": 100, "device": RTU_PROFILE})], baud=38400),
        bus("plc", "tcp://127.0.0.1:%d" % demo_port, "modbus-tcp",
            [("far", "modbus-tcp", 5, 4, {"poll_ms": 100, "device": RTU_PROFILE})]),
    ])
    socket = os.path.join(t.dir, "control.sock")
    with open(gateway.config_path) as f:
        text = f.read().replace('control_socket = ""', 'control_socket = "%s"' % socket)
    with open(gateway.config_path, "w") as f:
        f.write(text)
    config = gateway.config_path
    t.logs.append(("gateway", gateway.log_path))
    gateway.start()
    t.check("every sensor answers",
            wait_until(lambda: all(gateway.sensor(n).get("online")
                                   for n in ("boom", "mast", "tilt", "far")), 20))

    # Live, a Modbus RTU bus: Wireshark's own dissector, every CRC good.
    rtu_file = os.path.join(t.dir, "rtu1.pcapng")
    done = capture(t, tiltgate, config, "--bus", "rtu1", "--seconds", "2", "--output", rtu_file)
    t.check("a live capture of 2 s ends by itself with exit 0", done.returncode == 0,
            done.stderr.decode())
    t.check("it says how many frames it wrote", b"frame(s) of bus rtu1 (modbus-rtu)" in done.stderr,
            done.stderr.decode())
    rows = read_capture(t, rtu_file, ["frame.protocols", "mbrtu.crc16.status",
                                       "frame.comment", "frame.p2p_dir"])
    t.check("the capture holds both directions of 2 s of polls at 100 ms", len(rows) >= 20, rows)
    t.check("every packet is read by Wireshark's Modbus RTU dissector",
            rows and all("mbrtu" in r[0] for r in rows), rows[:4])
    t.check("every Modbus RTU CRC is good", rows and all(r[1] == "1" for r in rows), rows[:4])
    t.check("requests are outbound, replies inbound, each with the gateway's verdict",
            rows and all((r[3] == "0" and r[2] == "request") or (r[3] == "1" and r[2] == "CRC ok")
                         for r in rows), rows[:6])
    times = read_capture(t, rtu_file, ["frame.time_epoch"])
    epoch = [float(r[0]) for r in times]
    t.check("frames carry the time of their first byte, in order, from this run",
            epoch == sorted(epoch) and abs(epoch[-1] - time.time()) < 30, epoch[:3])

    # A Modbus TCP device's bus: Wireshark's own Modbus/TCP dissector, queries told from
    # responses by the ports the capture gives them.
    tcp_file = os.path.join(t.dir, "plc.pcapng")
    done = capture(t, tiltgate, config, "--bus", "plc", "--seconds", "2", "--output", tcp_file)
    rows = read_capture(t, tcp_file, ["frame.protocols", "_ws.col.Info"])
    malformed = read_capture(t, tcp_file, ["frame.number"], display_filter="_ws.malformed")
    t.check("a modbus-tcp bus's capture is read by Wireshark's Modbus/TCP dissector",
            done.returncode == 0 and len(rows) >= 20 and all("mbtcp" in r[0] for r in rows),
            rows[:4])
    t.check("its requests are queries and its replies responses, nothing malformed",
            rows and all(r[1].strip().startswith(("Query", "Response")) for r in rows) and
            sum(r[1].strip().startswith("Query") for r in rows) * 2 == len(rows) and
            not malformed, rows[:4])

    # Live to stdout, as `| wireshark -k -i -` reads it.
    piped = subprocess.run("%s capture --config %s --bus line1 --seconds 2 --output - | "
                           "HOME=%s tshark -r - -X lua_script:%s -T fields -e _ws.col.Info"
                           % (tiltgate, config, t.dir, LUA),
                           shell=True, capture_output=True, text=True, timeout=60)
    info = piped.stdout.splitlines()
    t.check("--output - streams a capture tshark reads from a pipe, Rieker functions named",
            any("Request: addr 223, Get Angle" in line for line in info) and
            any(line.startswith("Reply: addr 223, Get Angle") for line in info), info[:6])

    # The black box after a sensor's replies go bad.
    t.check("the simulator breaks boom's CRC", rieker.command("garbage 223") == "ok")
    said = wait_until(lambda: "black box holds its last 30 s" in gateway.log(20000), 20)
    t.check("the log says the black box holds what came before the sensor stopped answering",
            said, gateway.log())
    box = os.path.join(t.dir, "line1-last.pcapng")
    done = capture(t, tiltgate, config, "--bus", "line1", "--last", "--output", box)
    t.check("--last writes the black box at once, exit 0", done.returncode == 0,
            done.stderr.decode())
    rows = read_capture(t, box, ["tiltgate_rieker.crc.status", "frame.comment",
                                  "tiltgate_rieker.src", "_ws.col.Info"])
    bad = [r for r in rows if r[0] == "0"]
    good = [r for r in rows if r[0] == "1"]
    t.check("the Lua dissector flags the replies whose CRC the simulator broke, all boom's",
            bad and all(r[2] == "223" for r in bad), rows[-6:])
    t.check("the gateway's verdict on them is no reply: bad CRC",
            bad and all(r[1] == "no reply: bad CRC" for r in bad), bad[:3])
    t.check("the black box also holds the good replies from before, and mast's",
            any(r[2] == "223" for r in good) and any(r[2] == "101" for r in good), good[:3])
    t.check("the simulator answers again", rieker.command("answer 223") == "ok")

    # The audit trail: one record per capture.
    audit = subprocess.run([tiltgate, "audit", "--state-dir", os.path.join(t.dir, "state"),
                            "--setting", "capture", "--json", "--limit", "0"],
                           capture_output=True, text=True, timeout=30)
    records = json.loads(audit.stdout or "[]") if audit.returncode == 0 else []
    values = sorted(r.get("new_value", r.get("new", "")) for r in records)
    t.check("every capture is one audit record, door control socket",
            len(records) == 4 and all(r.get("door") == "control socket" for r in records) and
            "last 30 s" in values and "live 2 s" in values, (audit.stderr, records))

    # What goes wrong is said.
    done = capture(t, tiltgate, config, "--bus", "nosuch", "--seconds", "1", "--output",
                   os.path.join(t.dir, "x.pcapng"))
    t.check("a bus the gateway does not serve: exit 1, its buses named",
            done.returncode == 1 and b"line1" in done.stderr and b"rtu1" in done.stderr,
            done.stderr.decode())
    done = subprocess.run([tiltgate, "capture", "--control-socket", os.path.join(t.dir, "none.sock"),
                           "--bus", "line1", "--last", "--output", os.path.join(t.dir, "y.pcapng")],
                          capture_output=True, timeout=30)
    t.check("no gateway on the socket: exit 1, said", done.returncode == 1 and done.stderr,
            done.stderr.decode())
    for argv, why in ((["--bus", "line1", "--port", "/dev/null"], "both --bus and --port"),
                      (["--bus", "line1", "--last", "--seconds", "3"], "--last with --seconds"),
                      (["--port", "/dev/null", "--baud", "9600"], "--port without --protocol"),
                      ([], "neither --bus nor --port")):
        done = capture(t, tiltgate, config, *(argv + ["--output", os.path.join(t.dir, "z")]))
        t.check("a usage error (%s): exit 2, said" % why,
                done.returncode == 2 and b"tiltgate capture:" in done.stderr, done.stderr.decode())
    t.check("the gateway served on throughout", gateway.sensor("mast").get("online"))
    gateway.stop()


if __name__ == "__main__":
    sys.exit(Checks("capture").run(scenario))
