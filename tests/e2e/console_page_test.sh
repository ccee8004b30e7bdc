#!/usr/bin/env bash
# The console in Debian's headless Chromium: `tiltgate run` on a simulated Rieker bus with
# [http] users_file (accounts made by `tiltgate user add`, the password on standard input). The
# operator logs in through the page's form, zeroes the simulated sensor (the confirmation names
# it), and finds the change in the Audit tab; a viewer then sees no enabled action and no admin
# tab. A missing chromium fails, never skips.
# Usage: console_page_test.sh path/to/tiltgate
set -u
tiltgate=${1:?usage: $0 path/to/tiltgate}
here=$(cd "$(dirname "$0")" && pwd)
source "$here/support/script_lib.sh"
script_setup tiltgate-console
mkdir -p "$dir/state"
require_command chromium chromium

users="$dir/users"
add_user() {  # NAME ROLE PASSWORD
  printf '%s\n' "$3" | "$tiltgate" user add "$1" --role "$2" --users-file "$users" >>"$dir/users.log" 2>&1
}
if ! add_user oper operator 'op-secret-1' || ! add_user watcher viewer 'view-secret-2'; then
  echo "FAIL: tiltgate user add did not make the accounts:"; cat "$dir/users.log"
  echo "0 passed, 1 failed"
  exit 1
fi

start_sim "$tiltgate" rieker h6:223 "$dir/ttyUSB0"
port=$(free_port)
http_port=$(free_port)
cat >"$dir/plant.toml" <<TOML
[server]
listen = "127.0.0.1"
port = $port
control_socket = ""
state_dir = "$dir/state"

[http]
listen = "127.0.0.1"
port = $http_port
users_file = "$users"

[[bus]]
name = "line1"
port = "$dir/ttyUSB0"
protocol = "rieker"

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
unit_id = 1
TOML
"$tiltgate" run --config "$dir/plant.toml" >"$dir/gateway.out" 2>"$dir/gateway.err" &
pids+=($!)
healthy() { /usr/bin/python3 -c "import urllib.request as u; u.urlopen('http://127.0.0.1:$http_port/healthz', timeout=1)" 2>/dev/null; }
if ! wait_for 15 healthy; then
  echo "FAIL: the gateway's HTTP side did not come up"; tail -20 "$dir/gateway.err"
  echo "0 passed, 1 failed"
  exit 1
fi

if /usr/bin/python3 "$here/support/chromium_page.py" console "http://127.0.0.1:$http_port/" \
     'oper:op-secret-1' 'watcher:view-secret-2' boom zero; then
  echo "1 passed, 0 failed"
else
  echo "gateway log:"; tail -20 "$dir/gateway.err"
  echo "0 passed, 1 failed"
  exit 1
fi
