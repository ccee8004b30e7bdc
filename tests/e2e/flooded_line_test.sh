#!/usr/bin/env bash
# A flood of Modbus requests never makes a healthy sensor look dead (issue 51): one simulated H6
# polled every 100 ms with every bus key at its default, while 8 Modbus clients, each a process
# of its own (bench/modbus_load.cpp), read it as fast as the answers come for 10 s. Every read
# must be answered with the registers (no exception: 0x0B is what a broken cable looks like),
# and the gateway's log must not say the sensor answers late or stopped answering. The flood is
# the load of issue 51's report: on a 2-core machine it kept the kernel's tty worker from running
# for up to 2 s (docs/performance.md, "A flood and the line"). Nothing here is timed.
set -u
tiltgate=${1:?usage: flooded_line_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-flood
require_load_binary "$tiltgate"

start_sim "$tiltgate" rieker h6:223 "$dir/ttyUSB0"
port=$(free_port)
one_h6_config "$port" "$dir/ttyUSB0" >"$dir/plant.toml"
echo 'poll_ms = 100' >>"$dir/plant.toml"  # the last table is the sensor's
"$tiltgate" run --config "$dir/plant.toml" >"$dir/gateway.out" 2>&1 &
pids+=($!)
ready=""
for _ in $(seq 200); do
  if "$load" --port "$port" --clients 1 --function 4 --quantity 10 --seconds 0.05 >/dev/null 2>&1; then
    ready=yes; break
  fi
  sleep 0.05
done
[ -n "$ready" ] || { echo "FAIL: the gateway did not serve angles"; cat "$dir/gateway.out"; exit 1; }

# 8 clients, each its own process, as a PLC, an HMI, a historian and a few tools would be.
flood=()
for i in $(seq 8); do
  "$load" --port "$port" --clients 1 --function 4 --address 0 --quantity 10 --seconds 10 \
    --count-exceptions >"$dir/load.$i" 2>&1 &
  flood+=($!)
done
wait "${flood[@]}"

# all_answered: every client ran, read something, and got neither an error nor an exception.
all_answered() {
  local i out
  for i in $(seq 8); do
    out=$(cat "$dir/load.$i")
    echo "client $i: $out"
    [[ $out =~ requests=([0-9]+)\ errors=0\ .*exceptions=0 ]] && [ "${BASH_REMATCH[1]}" -gt 0 ] ||
      return 1
  done
}
# log_quiet: the log never blames the sensor.
log_quiet() {
  ! grep -E "answers late|stopped answering" "$dir/gateway.out"
}
check "8 clients flat out for 10 s: every read answered with registers, no exception" all_answered
check "the log says nothing of a late or silent sensor" log_quiet

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
