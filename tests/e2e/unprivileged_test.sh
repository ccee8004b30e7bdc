#!/usr/bin/env bash
# The gateway never needs root (docs/operations.md, "Running without root"). As root, the test plays both
# ways a gateway gets port 502 and its ttys without keeping root:
#  - [server] user: started as root, `tiltgate run` opens the tty and binds a port below 1024,
#    then serves as `nobody` (all its uids and gids, checked in /proc) and still reads the
#    sensor through the tty it opened; a user that does not exist is a fatal error.
#  - systemd socket activation: a listener bound by root on a port below 1024 is handed to a
#    gateway started as `nobody`, which serves Modbus on it.
# mbpoll reads unit 1's status word (holding register 1) each time.
set -u
tiltgate=${1:?usage: unprivileged_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
activate="$(dirname "$0")/support/socket_activate.py"
require_root
require_mbpoll
script_setup tiltgate-unprivileged
chmod 755 "$dir"
# What runs as nobody from the start needs a binary it may execute: the build tree may sit in
# a folder only root can enter (/root).
install -m 755 "$tiltgate" "$dir/tiltgate"
start_sim "$tiltgate" rieker h6:223 "$dir/tty"

# A free port below 1024 on loopback: only root (or a systemd socket) can bind it.
low_port() {
  /usr/bin/python3 - <<'PY'
import random, socket
for port in random.sample(range(600, 1000), 400):
    s = socket.socket()
    try:
        s.bind(("127.0.0.1", port))
    except OSError:
        continue
    print(port)
    break
PY
}

write_config() {  # PORT USER
  one_h6_config "$1" "$dir/tty" "$( [ -n "$2" ] && echo "user = \"$2\"" )" >"$dir/gateway.toml"
  chmod 644 "$dir/gateway.toml"
}

read_unit() {  # PORT
  for _ in $(seq 100); do
    mbpoll -m tcp -p "$1" -a 1 -t 4 -r 1 -c 1 -1 -o 2 127.0.0.1 >"$dir/read.out" 2>&1 && return 0
    sleep 0.1
  done
  return 1
}

ids_of() { awk '/^(Uid|Gid):/ {print $1, $2, $3, $4, $5}' "/proc/$1/status"; }

# 1. Started as root with user = "nobody".
port=$(low_port)
write_config "$port" nobody
"$tiltgate" run --config "$dir/gateway.toml" 2>"$dir/drop.err" &
gateway=$!
pids+=($gateway)
check "started as root with user = nobody, it serves port $port" read_unit "$port"
ids_of "$gateway" >"$dir/drop.ids"
check "every uid is nobody's" grep -qx "Uid: 65534 65534 65534 65534" "$dir/drop.ids"
check "every gid is nogroup's" grep -qx "Gid: 65534 65534 65534 65534" "$dir/drop.ids"
check "it says so in the log" grep -q "serving as user nobody (uid 65534)" "$dir/drop.err"
check "the tty opened as root still serves readings" \
  bash -c "sleep 0.5; mbpoll -m tcp -p $port -a 1 -t 3 -r 1 -c 2 -1 -o 2 127.0.0.1"
kill "$gateway"; wait "$gateway" 2>/dev/null

# 2. A user that does not exist: exit 1, never serving as root.
write_config "$(free_port)" tiltgate-no-such-user
timeout 20 "$tiltgate" run --config "$dir/gateway.toml" 2>"$dir/nouser.err"
check "a missing user exits 1" test $? -eq 1
check "a missing user is named" grep -qE "no user ['\"]tiltgate-no-such-user['\"]" "$dir/nouser.err"

# 3 and 4 start the gateway as nobody, which must be able to reach the binary at all: not so in
# a chroot whose root folder only root may enter (a test harness's, never a gateway's).
if ! setpriv --reuid=nobody --regid=nogroup --clear-groups "$dir/tiltgate" --help >/dev/null 2>&1; then
  echo "note: nobody cannot execute $dir/tiltgate here (a folder above it is closed to other users):"
  echo "      the checks that start the gateway as nobody are left out"
else
  # 3. Socket activation: root binds the low port, the gateway runs as nobody from the start.
  chmod 666 "$(readlink -f "$dir/tty")"
  port=$(low_port)
  write_config "$port" ""
  /usr/bin/python3 "$activate" --user nobody --listen "127.0.0.1:$port" -- \
    "$dir/tiltgate" run --config "$dir/gateway.toml" 2>"$dir/activated.err" &
  gateway=$!
  pids+=($gateway)
  check "started as nobody, it serves the low port systemd-style sockets gave it" read_unit "$port"
  check "it runs as nobody" grep -qx "Uid: 65534 65534 65534 65534" <(ids_of "$gateway")
  check "it says it took the passed socket" grep -q "serving on the socket systemd passed for port $port" "$dir/activated.err"
  kill "$gateway"; wait "$gateway" 2>/dev/null

  # 4. Without a socket or a privilege, a low port fails with the three ways out named.
  write_config "$(low_port)" ""
  timeout 20 setpriv --reuid=nobody --regid=nogroup --clear-groups "$dir/tiltgate" run \
    --config "$dir/gateway.toml" 2>"$dir/denied.err"
  check "an unprivileged bind of a low port exits 1" test $? -eq 1
  check "the error names the ways to get the port" grep -q "needs root, CAP_NET_BIND_SERVICE or a systemd socket" "$dir/denied.err"

fi

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
