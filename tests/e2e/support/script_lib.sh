# Shared by the tests/e2e/*.sh scripts that run build/tiltgate with Debian's Modbus clients:
# a scratch folder removed on exit with every process started, a free TCP port, a simulator on a
# pseudo-terminal, mbpoll required (a missing client fails, never skips), a mosquitto of the
# test's own, and pass/fail counts.
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

# require_root: skips the script (exit 77) unless it runs as root.
require_root() {
  [ "$(id -u)" = 0 ] && return 0
  echo "SKIP: needs root (scripts/test runs as root)"
  exit 77
}

# require_command COMMAND PACKAGE: fails the script when COMMAND is missing.
require_command() {
  command -v "$1" >/dev/null && return 0
  echo "FAIL: $1 not found (Debian package $2). Run scripts/setup."
  echo "0 passed, 1 failed"
  exit 1
}

# require_mbpoll: fails the script when Debian's mbpoll is missing.
require_mbpoll() {
  command -v mbpoll >/dev/null && return 0
  echo "FAIL: mbpoll not found (Debian package mbpoll). Run scripts/setup."
  echo "0 passed, 1 failed"
  exit 1
}

# require_load_binary TILTGATE: sets $load to the bench's load generator built beside TILTGATE
# (bench/modbus_load.cpp), or fails the script when it was not built.
require_load_binary() {
  load="$(dirname "$1")/bench/bench_modbus_load"
  [ -x "$load" ] && return 0
  echo "FAIL: $load not built (cmake --build build --target bench_modbus_load)"
  echo "0 passed, 1 failed"
  exit 1
}

# free_port: a random TCP port nothing listens on now, below the kernel's ephemeral range;
# never one it handed out before in this script (kept in $dir/.ports): the kernel gives a port
# just freed out again, and two listeners of one gateway on one port cannot both bind.
free_port() {
  local port
  for _ in $(seq 50); do
    # Below the kernel's ephemeral range (32768 up), so no connect() on the machine takes it
    # before the test's server binds it.
    port=$(/usr/bin/python3 -c 'import random, socket
for _ in range(1000):
    port = random.randint(20000, 32767)
    try:
        with socket.socket() as s:
            s.bind(("127.0.0.1", port))
        print(port)
        break
    except OSError:
        pass' 2>/dev/null || echo $((20000 + RANDOM % 12000)))
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

# wait_for SECONDS COMMAND...: true once the command succeeds, polled every 0.1 s.
wait_for() {
  local tries=$(($1 * 10)); shift
  for _ in $(seq "$tries"); do "$@" && return 0; sleep 0.1; done
  return 1
}

# require_broker: fails the script when Debian's mosquitto or its clients are missing; sets
# $mosquitto, and $broker_port to a free port for the test's own broker (never a system one).
require_broker() {
  mosquitto=$(command -v mosquitto || echo /usr/sbin/mosquitto)
  local missing=""
  [ -x "$mosquitto" ] || missing+="mosquitto not found (Debian package mosquitto). "
  command -v mosquitto_sub >/dev/null || missing+="mosquitto_sub not found (Debian package mosquitto-clients). "
  [ -x /usr/bin/python3 ] || missing+="/usr/bin/python3 not found (Debian package python3). "
  if [ -n "$missing" ]; then
    echo "FAIL: ${missing}Run scripts/setup."
    echo "0 passed, 1 failed"
    exit 1
  fi
  broker_port=$(free_port)
  # `user root`: started as root, mosquitto otherwise switches to its own user, and where that
  # user cannot read /etc/hosts.allow (a chroot whose root folder is 0700) Debian's build, which
  # checks every client with tcp-wrappers, refuses them all ("denied access by tcpd"). A test
  # broker on loopback keeps the test's user; for a non-root user the key has no effect.
  cat >"$dir/broker.conf" <<CONF
listener $broker_port 127.0.0.1
allow_anonymous true
persistence false
user root
CONF
}

# start_broker: the test's mosquitto on $broker_port, waiting (at most 5 s) until it takes a
# message; its pid in $broker_pid. stop_broker ends it.
start_broker() {
  "$mosquitto" -c "$dir/broker.conf" >>"$dir/broker.log" 2>&1 &
  broker_pid=$!
  pids+=($broker_pid)
  for _ in $(seq 100); do
    mosquitto_pub -p "$broker_port" -h 127.0.0.1 -t probe -m x 2>/dev/null && return 0
    sleep 0.05
  done
  echo "FAIL: mosquitto did not start"; cat "$dir/broker.log"; exit 1
}
stop_broker() { kill "$broker_pid"; wait "$broker_pid" 2>/dev/null; }
