#!/usr/bin/env bash
# The control socket is protected from the instant it exists, and a change made through it is
# logged with who made it (docs/operations.md, "Running without root"; docs/commissioning.md,
# "With the gateway running"). As root, `tiltgate run` is started under `umask 000` with every
# chmod it makes held back 3 s by strace (the window a bind-then-chmod socket would be open to
# anyone): the socket file must be mode 0660 as soon as it appears, and a connect as `nobody`
# must be refused throughout. Then a sensor re-addressed through the socket is logged with the
# Unix user and pid of the command that moved it (SO_PEERCRED).
set -u
tiltgate=${1:?usage: control_socket_access_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
require_root
require_command strace strace
if ! strace -f -o /dev/null true 2>/dev/null; then
  echo "FAIL: strace may not trace here (ptrace refused)"
  echo "0 passed, 1 failed"
  exit 1
fi
script_setup tiltgate-control-access
chmod 755 "$dir"
start_sim "$tiltgate" rieker h6:223 "$dir/tty"
socket="$dir/control.sock"
port=$(free_port)
one_h6_config "$port" "$dir/tty" "control_socket = \"$socket\"" | grep -v '^control_socket = ""' \
  >"$dir/gateway.toml"

# LeakSanitizer cannot run under ptrace (scripts/sanitize): under strace its check at exit
# could hang the sanitized gateway, so it is off for this one process.
(umask 000; [ -n "${ASAN_OPTIONS:-}" ] && export ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0"
 exec strace -f -o "$dir/strace.log" -e trace=chmod,fchmod,fchmodat \
  -e inject=chmod,fchmod,fchmodat:delay_enter=3000000 \
  "$tiltgate" run --config "$dir/gateway.toml") >"$dir/gateway.out" 2>"$dir/gateway.err" &
tracer=$!
pids+=($tracer)
# Both outputs go to files: a gateway left running must never hold the test's stdout open (ctest
# waits for it to close). end_gateway kills it by its command line (strace's too): strace ended
# by a signal leaves its tracee running, and on a loaded machine the tracee may not exist yet
# when the test looks for it by pid.
end_gateway() { pkill -9 -f -- "--config $dir/gateway.toml" 2>/dev/null; }
trap 'end_gateway; script_cleanup' EXIT

# nobody_connects: whether `nobody` can connect to the socket now.
nobody_connects() {
  setpriv --reuid=nobody --regid=nogroup --clear-groups /usr/bin/python3 -c "
import socket, sys
s = socket.socket(socket.AF_UNIX)
try:
    s.connect('$socket')
except OSError:
    sys.exit(1)
"
}
for _ in $(seq 200); do [ -S "$socket" ] && break; sleep 0.05; done
mode=$(stat -c %a "$socket" 2>/dev/null)
first_connect=refused
nobody_connects && first_connect=accepted
check "the control socket is made mode 0660 under umask 000 (it was $mode)" test "$mode" = 660
# Where nobody cannot run python at all (a folder above it closed to others), a refused connect
# proves nothing: the mode check above stands alone.
if setpriv --reuid=nobody --regid=nogroup --clear-groups /usr/bin/python3 -c pass 2>/dev/null; then
  check "nobody cannot connect the moment it appears" test "$first_connect" = refused
  for _ in $(seq 40); do
    nobody_connects && { first_connect=accepted; break; }
    sleep 0.1
  done
  check "nor in the seconds after" test "$first_connect" = refused
else
  echo "note: nobody cannot run /usr/bin/python3 here: the connect checks are left out"
fi

moved() {
  timeout 60 "$tiltgate" set --via-gateway --control-socket "$socket" --port "$dir/tty" \
    --address 223 address 9
}
check "a sensor is re-addressed through the control socket" moved
check "the log names the Unix user and pid that moved it" \
  grep -Eq "moved from address 223 to 9 by a commissioning command of user root \(uid 0, pid [0-9]+\)" \
  "$dir/gateway.err"

# Ended at once: nothing of its shutdown is this test's business, and none of it under strace.
end_gateway
[ "$failures" -eq 0 ] || { echo "gateway log:"; cat "$dir/gateway.err"; }
echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
