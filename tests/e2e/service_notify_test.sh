#!/usr/bin/env bash
# `tiltgate run` as a systemd Type=notify service (packaging/tiltgate.service): a unix datagram
# socket the test owns plays systemd's NOTIFY_SOCKET. Checked: READY=1 comes once the Modbus
# port is bound (a connection right after it succeeds); WATCHDOG=1 keeps coming when
# WATCHDOG_USEC and WATCHDOG_PID ask for it; SIGHUP gives RELOADING=1 then READY=1; SIGTERM
# gives STOPPING=1. With stderr as the journal's stream (JOURNAL_STREAM), every log line starts
# with its syslog priority and carries no timestamp.
set -u
tiltgate=${1:?usage: service_notify_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-notify
start_sim "$tiltgate" rieker h6:223 "$dir/tty"
port=$(free_port)
one_h6_config "$port" "$dir/tty" >"$dir/gateway.toml"

/usr/bin/python3 - "$tiltgate" "$dir" "$port" <<'PY'
import os, signal, socket, subprocess, sys

tiltgate, folder, port = sys.argv[1], sys.argv[2], int(sys.argv[3])
failures = []
passes = 0
def check(name, ok):
    global passes
    if ok:
        passes += 1
    else:
        failures.append(name)
        print("FAIL:", name)

listener = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
listener.bind(os.path.join(folder, "notify.sock"))
# Generous: the test waits for messages, it does not time them.
listener.settimeout(60)
log_path = os.path.join(folder, "gateway.log")
log = open(log_path, "w")
stream = os.fstat(log.fileno())
env = dict(os.environ, NOTIFY_SOCKET=os.path.join(folder, "notify.sock"),
           WATCHDOG_USEC="200000", JOURNAL_STREAM=f"{stream.st_dev}:{stream.st_ino}")
# WATCHDOG_PID must be the gateway's own pid, as systemd sets it: the shell's, kept by exec.
gateway = subprocess.Popen(
    ["sh", "-c", 'WATCHDOG_PID=$$; export WATCHDOG_PID; exec "$0" run --config "$1"',
     tiltgate, os.path.join(folder, "gateway.toml")], env=env, stderr=log)

def next_message():
    try:
        return listener.recv(4096).decode()
    except socket.timeout:
        return None

def wait_for(wanted, skip=("WATCHDOG=1",)):
    """The next message other than a heartbeat; it must contain `wanted`."""
    while True:
        message = next_message()
        if message is None:
            return f"(nothing for 60 s, waiting for {wanted})"
        if message not in skip:
            return message

try:
    first = wait_for("READY=1", skip=())
    check(f"READY=1 first, got {first!r}", first == "READY=1")
    if first != "READY=1":
        raise SystemExit(1)  # nothing else would come either
    try:
        socket.create_connection(("127.0.0.1", port), timeout=5).close()
        bound = True
    except OSError:
        bound = False
    check("the Modbus port accepts once READY=1 is sent", bound)
    beats = [next_message() for _ in range(5)]
    check(f"WATCHDOG=1 keeps coming, got {beats!r}", beats == ["WATCHDOG=1"] * 5)
    gateway.send_signal(signal.SIGHUP)
    reloading = wait_for("RELOADING=1")
    check(f"RELOADING=1 on SIGHUP, got {reloading!r}",
          reloading.startswith("RELOADING=1\nMONOTONIC_USEC="))
    ready = wait_for("READY=1")
    check(f"READY=1 after the reload, got {ready!r}", ready == "READY=1")
    gateway.send_signal(signal.SIGTERM)
    stopping = wait_for("STOPPING=1")
    check(f"STOPPING=1 on SIGTERM, got {stopping!r}", stopping == "STOPPING=1")
    check("exit 0 after SIGTERM", gateway.wait(timeout=60) == 0)
finally:
    if gateway.poll() is None:
        gateway.kill()
log.close()
lines = open(log_path).read().splitlines()
check("the gateway logged", len(lines) > 0)
for line in lines:
    check(f"journal line with a priority prefix and no timestamp: {line!r}",
          len(line) > 3 and line[0] == "<" and line[1] in "01234567" and line[2] == ">"
          and not line[3:7].isdigit())
check("the start-up line is info (<6>)", any(l.startswith("<6>serving 1 sensor(s)") for l in lines))
check("the reload line is info (<6>)", any(l.startswith("<6>SIGHUP: reloading") for l in lines))
print(f"{passes} passed, {len(failures)} failed")
sys.exit(1 if failures else 0)
PY
