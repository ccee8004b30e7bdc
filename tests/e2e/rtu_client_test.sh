#!/usr/bin/env bash
# End to end with a real Modbus RTU client: mbpoll (Debian's package) reads the simulated RTU
# inclinometers of `tiltgate sim modbus-rtu` directly on its pseudo-terminal, then
# `tiltgate run` polls the same simulator through device profiles, and mbpoll over TCP must
# read from the gateway what it read on the wire, after each profile's type, word order and
# scale. A missing mbpoll is a failure, never a skip: scripts/setup installs it.
set -u
tiltgate=${1:?usage: rtu_client_test.sh path/to/tiltgate}
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
source "$(dirname "$0")/support/script_lib.sh"
require_mbpoll
script_setup tiltgate-rtu-client
# The values mbpoll prints, one per line: a 16-bit register's signed value where it shows one
# ("[6]: 65436 (-100)"), else the value ("[1]: 2.5").
values() {
  awk '/^\[[0-9]+\]:/ { v = $2; if ($3 ~ /^\(/) { v = $3; gsub(/[()]/, "", v) } print v }'
}
# Every wait is bounded: mbpoll's own time-out, and `timeout` around it in case it hangs.
mb_rtu() { timeout 20 mbpoll -m rtu -b 19200 -P even -1 -o 2 "$@" "$dir/ttyRtu"; }
mb_tcp() { timeout 20 mbpoll -m tcp -p "$port" -1 -o 2 "$@" 127.0.0.1; }

# Two inclinometers of the simulator's preset (examples/devices/rtu-inclinometer.toml): the
# --sensors parser gives slave i the angles X = 1 + i, Y = -(1 + i).
start_sim "$tiltgate" modbus-rtu modbus-rtu:1,modbus-rtu:7 "$dir/ttyRtu"

# 1. mbpoll on the wire. mbpoll's -r is 1-based: the profiles' address 0 is -r 1.
# Slave 1 as the example profile reads it: angle_x, angle_y at input 0 and 2, float32 ABCD
# (mbpoll's -B).
mb_rtu -a 1 -t 3:float -B -r 1 -c 2 >"$dir/rtu-float.out" 2>&1 ||
  { echo "FAIL: mbpoll -m rtu could not read slave 1"; cat "$dir/rtu-float.out"; exit 1; }
read -r -d '' wire_x1 wire_y1 < <(values <"$dir/rtu-float.out")
# Slave 7 as an int16 profile reads it: input 4 and 5, int16 in 0.01 degree.
mb_rtu -a 7 -t 3 -r 5 -c 2 >"$dir/rtu-int16.out" 2>&1 ||
  { echo "FAIL: mbpoll -m rtu could not read slave 7"; cat "$dir/rtu-int16.out"; exit 1; }
read -r -d '' raw_x7 raw_y7 < <(values <"$dir/rtu-int16.out")
echo "on the wire: slave 1 float32 ($wire_x1, $wire_y1), slave 7 int16 ($raw_x7, $raw_y7)" \
  >>"$dir/checks.log"
# The simulator's values, so a comparison below cannot pass on two empty reads.
wire_values_ok() {
  awk -v x="$wire_x1" -v y="$wire_y1" -v rx="$raw_x7" -v ry="$raw_y7" \
    'BEGIN { exit !(x == 1 && y == -1 && rx == 200 && ry == -200) }'
}
check "mbpoll -m rtu reads the simulated slaves' angles on the pseudo-terminal" wire_values_ok

# 2. The gateway on the same simulator (mbpoll -1 has exited and closed the port): slave 1
# through the example profile, slave 7 through a profile of the int16 registers only.
cp "$source_dir/examples/devices/rtu-inclinometer.toml" "$dir/rtu-inclinometer.toml"
cat >"$dir/rtu-int16.toml" <<'TOML'
description = "The same inclinometer read as int16 in 0.01 degree"

[[read]]
table = "input"
address = 4
count = 2

[[value]]
name = "angle_x"
table = "input"
address = 4
type = "int16"
scale = 0.01

[[value]]
name = "angle_y"
table = "input"
address = 5
type = "int16"
scale = 0.01
TOML
# A port nothing listens on now (the system picks it), or a random one without python3.
port=$(free_port)
cat >"$dir/plant.toml" <<TOML
[server]
listen = "127.0.0.1"
port = $port

[[bus]]
name = "rtu-line"
port = "$dir/ttyRtu"
protocol = "modbus-rtu"
baud = 19200
timeout_ms = 200

[[sensor]]
name = "float-inclinometer"
bus = "rtu-line"
model = "modbus-rtu"
address = 1
unit_id = 1
poll_ms = 50
device = "rtu-inclinometer.toml"

[[sensor]]
name = "int16-inclinometer"
bus = "rtu-line"
model = "modbus-rtu"
address = 7
unit_id = 2
poll_ms = 50
device = "rtu-int16.toml"
TOML
"$tiltgate" run --config "$dir/plant.toml" 2>"$dir/gateway.err" &
pids+=($!)
# Both units online (status bit 0) before comparing.
online() {
  mb_tcp -a "$1" -t 3 -r 7 -c 1 2>/dev/null | values |
    awk '{ status = $1; n++ } END { exit !(n == 1 && status % 2 == 1) }'
}
ready=""
for _ in $(seq 100); do
  if online 1 && online 2; then ready=yes; break; fi
  sleep 0.1
done
if [ -z "$ready" ]; then
  echo "FAIL: the gateway did not bring both units online"
  cat "$dir/gateway.err"
  exit 1
fi

# The gateway's common block: angle_x, angle_y float32 at input 0 and 2 (ABCD, the default
# word order) and in 0.01 degree at input 4 and 5.
gateway_agrees() {  # gateway_agrees UNIT X Y: the unit's angles equal X and Y degrees
  local unit=$1 x=$2 y=$3 gx gy cx cy
  read -r -d '' gx gy < <(mb_tcp -a "$unit" -t 3:float -B -r 1 -c 2 | values)
  read -r -d '' cx cy < <(mb_tcp -a "$unit" -t 3 -r 5 -c 2 | values)
  echo "unit $unit: expected ($x, $y), float32 ($gx, $gy), 0.01 degree ($cx, $cy)"
  awk -v x="$x" -v y="$y" -v gx="$gx" -v gy="$gy" -v cx="$cx" -v cy="$cy" 'BEGIN {
    d = 1e-6
    exit !(gx != "" && cx != "" && (gx - x)^2 < d && (gy - y)^2 < d && (cx - 100 * x)^2 < d &&
           (cy - 100 * y)^2 < d)
  }'
}
check "the gateway reads slave 1's float32 ABCD angles as mbpoll read them on the wire" \
  gateway_agrees 1 "$wire_x1" "$wire_y1"
scaled_x7=$(awk -v r="$raw_x7" 'BEGIN { print r * 0.01 }')
scaled_y7=$(awk -v r="$raw_y7" 'BEGIN { print r * 0.01 }')
check "the gateway reads slave 7's int16 angles as mbpoll read them, times the profile's 0.01" \
  gateway_agrees 2 "$scaled_x7" "$scaled_y7"

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
