# Shared by the tests/e2e/*.sh scripts that run build/tiltgate with Debian's Modbus clients:
# a scratch folder removed on exit with every process started, a free TCP port, a simulator on a
# pseudo-terminal, mbpoll required (a missing client fails, never skips), and pass/fail counts.
# Source it after `set -u`; it sets $dir, $pids, $passes and $failures.

# script_setup PREFIX: the scratch folder /tmp/PREFIX-XXXXXX and the exit trap.
script_setup() {
  dir=$(mktemp -d "/tmp/$1-XXXXXX")
  pids=()
  passes=0
  failures=0
  trap script_cleanup EXIT
  trap 'exit 1' INT TERM
}

# KEEP_DIR=1 keeps the scratch folder for a look after a failure.
script_cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null; done
  wait 2>/dev/null
  [ -n "${KEEP_DIR:-}" ] || rm -rf "$dir"
}

# require_mbpoll: fails the script when Debian's mbpoll is missing.
require_mbpoll() {
  command -v mbpoll >/dev/null && return 0
  echo "FAIL: mbpoll not found (Debian package mbpoll). Run scripts/setup."
  echo "0 passed, 1 failed"
  exit 1
}

# free_port: a TCP port nothing listens on now (the kernel's choice), or a random high one;
# never one it handed out before in this script (kept in $dir/.ports): the kernel gives a port
# just freed out again, and two listeners of one gateway on one port cannot both bind.
free_port() {
  local port
  for _ in $(seq 50); do
    port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])' \
      2>/dev/null || echo $((20000 + RANDOM % 20000)))
    grep -qx "$port" "${dir:?}/.ports" 2>/dev/null || break
  done
  echo "$port" >>"$dir/.ports"
  echo "$port"
}

# start_sim TILTGATE FAMILY SENSORS LINK: `tiltgate sim FAMILY` in the background, waiting
# (at most 5 s) for its pseudo-terminal's link.
start_sim() {
  "$1" sim "$2" --sensors "$3" --link "$4" >"$dir/sim.out" 2>"$dir/sim.err" &
  pids+=($!)
  wait_for_link "$4" && return 0
  echo "FAIL: the simulator did not start"
  cat "$dir/sim.err"
  exit 1
}

# wait_for_link LINK: waits (at most 5 s) for a simulator's link to its pseudo-terminal.
wait_for_link() {
  for _ in $(seq 100); do [ -e "$1" ] && return 0; sleep 0.05; done
  return 1
}

# check NAME COMMAND...: counts a pass when the command succeeds, else a failure with its log.
check() {
  local name=$1; shift
  if "$@" >>"$dir/checks.log" 2>&1; then
    passes=$((passes + 1))
  else
    failures=$((failures + 1)); echo "FAIL: $name"; tail -8 "$dir/checks.log"
  fi
}

# one_h6_config PORT TTY [SERVER_LINES]: a configuration of one H6 (address 223, unit 1) on
# TTY, Modbus on 127.0.0.1:PORT, no HTTP and no control socket; SERVER_LINES (one or more
# lines) go into [server] as they are.
one_h6_config() {
  cat <<TOML
[server]
listen = "127.0.0.1"
port = $1
control_socket = ""
${3:-}

[http]
enabled = false

[[bus]]
name = "line1"
port = "$2"
protocol = "rieker"

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
unit_id = 1
TOML
}
