#!/usr/bin/env bash
# The benchmark's load generator (bench/modbus_load.cpp) against `tiltgate demo`, briefly: every
# reply it got must be correct and every request answered, so the bench tool cannot rot. Nothing
# here is timed: the checks are on counts only.
set -u
tiltgate=${1:?usage: modbus_load_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-load
load="$(dirname "$tiltgate")/bench/bench_modbus_load"
if [ ! -x "$load" ]; then
  echo "FAIL: $load not built (cmake --build build --target bench_modbus_load)"
  echo "0 passed, 1 failed"
  exit 1
fi

port=$(free_port)
"$tiltgate" demo --listen 127.0.0.1 --port "$port" --http-port 0 >"$dir/demo.out" 2>"$dir/demo.err" &
pids+=($!)
for _ in $(seq 200); do
  "$load" --port "$port" --clients 1 --function 4 --quantity 1 --seconds 0.05 >/dev/null 2>&1 && break
  sleep 0.05
done

# answered LOAD-ARGS...: the run exits 0 and reports some requests and no errors.
answered() {
  local out
  out=$("$load" --port "$port" "$@") || { echo "$out"; return 1; }
  echo "$out"
  [[ $out =~ requests=([0-9]+)\ errors=0 ]] && [ "${BASH_REMATCH[1]}" -gt 0 ]
}
# Unit 1 (an H6): input registers 0..37 and holding registers 0..7 are mapped.
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
