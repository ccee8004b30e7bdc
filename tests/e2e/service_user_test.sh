#!/usr/bin/env bash
# Started as root with `[server] user`, every file the gateway writes is that user's, and every
# feed works (docs/operations.md, "Running without root" and "The state directory"): the test
# makes a throwaway system user (removed on exit) and starts `tiltgate run` as root with that
# user, a state_dir and a control socket folder that do not exist yet, [mqtt] and [sparkplug]
# to a mosquitto of its own, the control socket and [http]. Sparkplug's NBIRTH and the JSON
# feed's states arrive, a commissioning command through the control socket is answered, HTTP
# answers, and the state_dir, its files and the socket all belong to the user. A reload
# (SIGHUP) that adds a bus restarts the control socket, as that user: it answers for the new
# bus, and nothing is logged as failed. Then, with folders an older gateway made as root, the
# edge node and the control socket are off until the folders are given to the user, and then
# back by themselves within seconds: no restart, no reload.
set -u
tiltgate=${1:?usage: service_user_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
require_root
require_command useradd passwd
script_setup tiltgate-service-user
chmod 755 "$dir"
user=tgate-e2e-$$
useradd --system --user-group --no-create-home --home-dir /nonexistent --shell /usr/sbin/nologin "$user" || {
  echo "FAIL: cannot make user $user"; echo "0 passed, 1 failed"; exit 1; }
trap 'script_cleanup; userdel "$user" 2>/dev/null; groupdel "$user" 2>/dev/null' EXIT
# Where a folder above the test's is closed to others (a chroot whose root is 0700), the user
# cannot reach its files at all: nothing here could be shown, so the test is skipped.
if ! setpriv --reuid="$user" --regid="$user" --clear-groups test -x "$dir"; then
  echo "skipped: user $user cannot reach $dir (a folder above it is closed to others)"
  exit 77
fi

require_broker
start_broker
mosquitto_sub -h 127.0.0.1 -p "$broker_port" -v -t 'spBv1.0/#' -t 'e2e/#' >"$dir/sub.out" 2>"$dir/sub.err" &
pids+=($!)

start_sim "$tiltgate" rieker h6:223 "$dir/tty1"
"$tiltgate" sim rieker --sensors h6:101 --link "$dir/tty2" >"$dir/sim2.out" 2>"$dir/sim2.err" &
pids+=($!)
wait_for_link "$dir/tty2"
# The bus a reload adds is opened as the user.
chmod 666 "$(readlink -f "$dir/tty2")"

state="$dir/lib/tiltgate"
socket="$dir/run/control.sock"
modbus_port=$(free_port)
http_port=$(free_port)
write_config() {  # EXTRA_TABLES: one_h6_config with the control socket, HTTP and both feeds
  { one_h6_config "$modbus_port" "$dir/tty1" "user = \"$user\"" |
      sed -e "s|^control_socket = \"\"|control_socket = \"$socket\"|" \
          -e "s|^user = \"$user\"|user = \"$user\"\nstate_dir = \"$state\"|" \
          -e "s|^enabled = false|port = $http_port|"
    cat <<TOML

[mqtt]
host = "127.0.0.1"
port = $broker_port
topic_prefix = "e2e/gw"
interval_ms = 200
state_dir = "$state"

[sparkplug]
host = "127.0.0.1"
port = $broker_port
group_id = "e2e"
edge_node_id = "gw"
state_dir = "$state"
$1
TOML
  } >"$dir/gateway.toml"
  chmod 644 "$dir/gateway.toml"
}
write_config ""
"$tiltgate" run --config "$dir/gateway.toml" 2>"$dir/gateway.err" &
gateway=$!
pids+=($gateway)

http_answers() {
  /usr/bin/python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$http_port/api/sensors', timeout=5).read()"
}
through() {  # TTY ADDRESS: `tiltgate info` through the control socket
  timeout 30 "$tiltgate" info --via-gateway --control-socket "$socket" --port "$1" --address "$2"
}
not_users() { find "$state" "$dir/run" ! -user "$user" -o ! -group "$user"; }
owned_by_user() {
  [ -z "$(not_users)" ] && [ -n "$(find "$state" -path '*sparkplug/bdSeq')" ] && [ -S "$socket" ]
}
no_failure_logged() {
  ! grep -Ei " (error|critical) |control socket off|permission denied|not stored|failed" "$dir/gateway.err"
}

check "it serves as the user" wait_for 20 grep -q "serving as user $user" "$dir/gateway.err"
check "the edge node's NBIRTH arrives" wait_for 20 grep -q "^spBv1.0/e2e/NBIRTH/gw " "$dir/sub.out"
check "the JSON feed's states arrive" wait_for 20 grep -q "^e2e/gw/boom/state " "$dir/sub.out"
check "a command through the control socket is answered" through "$dir/tty1" 223
check "HTTP answers" wait_for 10 http_answers
check "the state_dir, its files and the control socket are the user's" owned_by_user
not_users >"$dir/not-users.before"

write_config "
[[bus]]
name = \"line2\"
port = \"$dir/tty2\"
protocol = \"rieker\"

[[sensor]]
name = \"mast\"
bus = \"line2\"
model = \"h6\"
address = 101
unit_id = 2"
kill -HUP "$gateway"
check "the reload is applied" wait_for 20 grep -q "configuration reloaded from .*restarted: .*control socket" "$dir/gateway.err"
check "after the reload the control socket answers for the new bus" through "$dir/tty2" 101
check "and for the old one" through "$dir/tty1" 223
check "after the reload every file is still the user's" owned_by_user
check "nothing is logged as failed" no_failure_logged
check "the gateway is still running" kill -0 "$gateway"
kill "$gateway"; wait "$gateway" 2>/dev/null

# Folders an older gateway made as root: the edge node and the control socket are off and say
# why; given to the user, both come back by themselves (tried every 10 s): no restart, no reload.
state="$dir/old/tiltgate"
socket="$dir/old/run/control.sock"
mkdir -p "$state/sparkplug" "$dir/old/run"
write_config ""
"$tiltgate" run --config "$dir/gateway.toml" 2>"$dir/old.err" &
gateway=$!
pids+=($gateway)
births() { grep -c "^spBv1.0/e2e/NBIRTH/gw " "$dir/sub.out"; }
check "a root-owned state_dir turns the edge node off, saying why" \
  wait_for 20 grep -q "Sparkplug edge node off: state_dir .* is not writable" "$dir/old.err"
check "a root-owned socket folder turns the control socket off, saying why" \
  grep -q "control socket off: .*Permission denied" "$dir/old.err"
before=$(births)
chown -R "$user:" "$dir/old"
more_births() { [ "$(births)" -gt "$before" ]; }
check "given to the user, the edge node starts by itself, without a reload" wait_for 30 more_births
socket_back() { [ -S "$socket" ]; }
check "and the control socket" wait_for 30 socket_back
check "which answers" through "$dir/tty1" 223

[ "$failures" -eq 0 ] || { echo "not the user's:"; cat "$dir/not-users.before"; not_users; echo "gateway log:"; cat "$dir/gateway.err"; }
echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
