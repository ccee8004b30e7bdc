#!/usr/bin/env bash
# Idle connections and allow lists against `tiltgate run` on a simulated Rieker bus: 32 silent
# connections (8 from each of four addresses) no longer lock out a PLC, a ninth connection from
# one address replaces that address's oldest, a host outside [server] allow is closed at once,
# and one outside write_allow reads but gets exception 01 for a write. Clients bind loopback
# addresses (127.0.0.0/8) to be different hosts.
set -u
tiltgate=${1:?usage: access_limits_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-access
[ -x /usr/bin/python3 ] || { echo "FAIL: /usr/bin/python3 not found"; echo "0 passed, 1 failed"; exit 1; }

start_sim "$tiltgate" rieker h6:223 "$dir/ttyUSB0"
port=$(free_port)
cat >"$dir/plant.toml" <<TOML
[server]
listen = "127.0.0.1"
port = $port
writes = true
allow = ["127.0.0.1", "127.0.0.2/31", "127.0.0.4/30"]
write_allow = ["127.0.0.1"]

[http]
enabled = false

[[bus]]
name = "line1"
port = "$dir/ttyUSB0"
protocol = "rieker"
timeout_ms = 100

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
unit_id = 1
poll_ms = 50
TOML
"$tiltgate" run --config "$dir/plant.toml" 2>"$dir/gateway.err" &
pids+=($!)

# The checks in one Python run (the silent connections must stay open across them); each
# prints "PASS name" or "FAIL name".
(cd "$dir" && /usr/bin/python3 - "$port") >"$dir/results.txt" 2>&1 <<'PY'
import socket, struct, sys, time
port = int(sys.argv[1])

def connect(source):
    s = socket.socket()
    s.settimeout(5)
    s.bind((source, 0))
    s.connect(("127.0.0.1", port))
    return s

def ask(s, function, address, value_or_count, transaction=1):
    s.sendall(struct.pack(">HHHBBHH", transaction, 0, 6, 1, function, address, value_or_count))
    reply = b""
    while len(reply) < 9:
        chunk = s.recv(64)
        if not chunk:
            return None
        reply += chunk
    return reply

def closed(s):
    try:
        return s.recv(1) == b""
    except (ConnectionResetError, socket.timeout):
        return False

def report(name, ok):
    print(("PASS " if ok else "FAIL ") + name, flush=True)

# Wait until the gateway answers reads.
for _ in range(200):
    try:
        s = connect("127.0.0.1")
        reply = ask(s, 4, 0, 2)
        s.close()
        if reply and reply[7] == 4:
            break
    except OSError:
        pass
    time.sleep(0.05)

silent = {}
for host in ("127.0.0.2", "127.0.0.3", "127.0.0.4", "127.0.0.5"):
    silent[host] = []
    for _ in range(8):
        silent[host].append(connect(host))
        time.sleep(0.01)  # accepted in this order: the first is idle longest
time.sleep(0.2)
plc = connect("127.0.0.1")
reply = ask(plc, 4, 0, 2)
report("a read on a new connection is answered with 32 silent ones open", reply is not None and reply[7] == 4)
report("the connection idle longest made room for it", closed(silent["127.0.0.2"][0]))

ninth = connect("127.0.0.3")
reply = ask(ninth, 4, 0, 2)
report("a ninth connection from one address is answered", reply is not None and reply[7] == 4)
report("it replaced that address's oldest", closed(silent["127.0.0.3"][0]))
reply = ask(silent["127.0.0.4"][0], 4, 0, 2)
report("another address's oldest connection is untouched", reply is not None and reply[7] == 4)

stranger = connect("127.0.0.9")
report("a host outside allow is closed at once", closed(stranger))

panel = silent["127.0.0.5"][1]
reply = ask(panel, 6, 0, 2)
report("a write from outside write_allow gets exception 01", reply is not None and reply[7:9] == b"\x86\x01")
reply = ask(panel, 3, 0, 1)
report("its reads still work", reply is not None and reply[7] == 3)
reply = ask(plc, 6, 0, 2)
report("a write from inside write_allow is carried out", reply is not None and reply[7] == 6)
PY
passes=$(grep -c '^PASS' "$dir/results.txt")
failures=$(grep -c '^FAIL' "$dir/results.txt")
[ $((passes + failures)) -eq 9 ] || failures=$((failures + 1))
grep -v '^PASS' "$dir/results.txt"
[ "$failures" -eq 0 ] || tail -20 "$dir/gateway.err"
echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
