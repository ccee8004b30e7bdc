#!/usr/bin/env bash
# Pass-through with Debian's mbpoll: `tiltgate run` on a Modbus RTU bus served by
# `tiltgate sim modbus-rtu` (inclinometers at slaves 17 and 30), the one at 17 cached as
# unit 3, slave 30 passed through as unit 30. mbpoll reads unit 30's own input registers
# through the gateway; unit 31 is nobody's. A missing mbpoll is a failure, never a skip.
set -u
tiltgate=${1:?usage: pass_through_mbpoll_test.sh path/to/tiltgate}
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
source "$(dirname "$0")/support/script_lib.sh"
require_mbpoll
script_setup tiltgate-pass
start_sim "$tiltgate" modbus-rtu modbus-rtu:17,modbus-rtu:30 "$dir/ttyRtu"
port=$(free_port)
cat >"$dir/pass.toml" <<TOML
[server]
listen = "127.0.0.1"
port = $port

[[bus]]
name = "rtu-line"
port = "$dir/ttyRtu"
protocol = "modbus-rtu"
timeout_ms = 100
pass_through = [30]

[[sensor]]
name = "boom"
bus = "rtu-line"
model = "modbus-rtu"
address = 17
unit_id = 3
device = "$source_dir/examples/devices/rtu-inclinometer.toml"
TOML
"$tiltgate" run --config "$dir/pass.toml" 2>"$dir/gateway.err" &
pids+=($!)

# The simulator gives slave 30 (its second device) angle X = 2 degrees, a float32 ABCD at
# input register 0 of the device itself: only pass-through can show it on unit 30.
read_x() {
  mbpoll -m tcp -p "$port" -a 30 -t 3:float -B -r 1 -c 1 -1 -o 2 127.0.0.1 >"$dir/x.out" 2>&1
}
for _ in $(seq 200); do read_x && break; sleep 0.05; done
if ! awk '/^\[1\]:/ {x=$2} END {exit !(x > 1.9 && x < 2.1)}' "$dir/x.out"; then
  echo "FAIL: mbpoll did not read slave 30's angle through unit 30"
  cat "$dir/x.out" "$dir/gateway.err"
  exit 1
fi
# Unit 31 is neither a sensor nor passed through: 0x0A, so mbpoll fails.
if mbpoll -m tcp -p "$port" -a 31 -t 3 -r 1 -c 1 -1 -o 2 127.0.0.1 >"$dir/none.out" 2>&1; then
  echo "FAIL: unit 31 answered"
  cat "$dir/none.out"
  exit 1
fi
echo "2 passed, 0 failed"
