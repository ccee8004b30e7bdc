#!/usr/bin/env bash
# The benchmark's load generator (bench/modbus_load.cpp) against build/tiltgate, briefly: every
# reply it got must be correct and every request answered, so the bench tool cannot rot. Nothing
# here is timed: the checks are on counts only.
set -u
tiltgate=${1:?usage: modbus_load_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-load
require_load_binary "$tiltgate"

# `tiltgate run` on a simulated H6 with a long reply wait: on one event loop a flood of TCP
# requests still delays bus transactions, and the default 50 ms wait can take the sensor
# offline for a moment (its reads then answer 0x0B); that is the bus benchmark's business.
start_sim "$tiltgate" rieker h6:223 "$dir/ttyUSB0"
port=$(free_port)
cat >"$dir/plant.toml" <<TOML
[server]
listen = "127.0.0.1"
port = $port
control_socket = ""

[http]
enabled = false

[[bus]]
name = "line1"
port = "$dir/ttyUSB0"
protocol = "rieker"
timeout_ms = 2000

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
unit_id = 1
poll_ms = 50
TOML
"$tiltgate" run --config "$dir/plant.toml" >"$dir/gateway.out" 2>&1 &
pids+=($!)
ready=""
for _ in $(seq 200); do
  if "$load" --port "$port" --clients 1 --function 4 --quantity 2 --seconds 0.05 >/dev/null 2>&1; then
    ready=yes; break
  fi
  sleep 0.05
done
[ -n "$ready" ] || { echo "FAIL: the gateway did not serve angles"; cat "$dir/gateway.out"; exit 1; }

# answered LOAD-ARGS...: the run exits 0 and reports some requests and no errors.
answered() {
  local out
  out=$("$load" --port "$port" "$@") || { echo "$out"; return 1; }
  echo "$out"
  [[ $out =~ requests=([0-9]+)\ errors=0 ]] && [ "${BASH_REMATCH[1]}" -gt 0 ]
}
# Unit 1 (an H6, built-in map): input registers 0..37 and holding registers 0..7.
check "4 clients read 10 input registers for 1 s" \
  answered --clients 4 --function 4 --address 0 --quantity 10 --seconds 1
check "4 clients read the 38-register common block" \
  answered --clients 4 --function 4 --address 0 --quantity 38 --seconds 0.5
check "4 clients read the 8 holding registers" \
  answered --clients 4 --function 3 --address 0 --quantity 8 --seconds 0.5
# And the checks themselves: an unmapped register is answered 0x02, which the load generator
# must count as an error rather than as a fast reply.
check "an exception reply counts as an error" \
  bash -c "! '$load' --port $port --clients 1 --function 4 --address 1000 --quantity 1 --seconds 0.2"

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
