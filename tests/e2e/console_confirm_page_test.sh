#!/usr/bin/env bash
# The apply's confirmation window in Debian's headless Chromium (issue 52, item 7;
# docs/web-console.md, "Applying with a confirmation window"): an admin edits the file in the
# Configuration tab and applies it; the page shows the countdown and a Confirm button, and
# Confirm keeps the file (no window left on disk). A missing chromium fails, never skips.
# Usage: console_confirm_page_test.sh path/to/tiltgate
set -u
tiltgate=${1:?usage: $0 path/to/tiltgate}
here=$(cd "$(dirname "$0")" && pwd)
source "$here/support/script_lib.sh"
script_setup tiltgate-console-confirm
mkdir -p "$dir/state"
require_command chromium chromium

users="$dir/users"
if ! printf '%s\n' 'admin-secret-3' |
     "$tiltgate" user add boss --role admin --users-file "$users" >"$dir/users.log" 2>&1; then
  echo "FAIL: tiltgate user add did not make the account:"; cat "$dir/users.log"
  echo "0 passed, 1 failed"
  exit 1
fi

start_sim "$tiltgate" rieker h6:223 "$dir/ttyUSB0"
port=$(free_port)
http_port=$(free_port)
{ one_h6_config "$port" "$dir/ttyUSB0" "state_dir = \"$dir/state\"" |
    sed "s|^enabled = false|listen = \"127.0.0.1\"\nport = $http_port\nusers_file = \"$users\"|"
} >"$dir/plant.toml"
"$tiltgate" run --config "$dir/plant.toml" >"$dir/gateway.out" 2>"$dir/gateway.err" &
pids+=($!)
healthy() { /usr/bin/python3 -c "import urllib.request as u; u.urlopen('http://127.0.0.1:$http_port/healthz', timeout=1)" 2>/dev/null; }
if ! wait_for 15 healthy; then
  echo "FAIL: the gateway's HTTP side did not come up"; tail -20 "$dir/gateway.err"
  echo "0 passed, 1 failed"
  exit 1
fi

check "the page shows the countdown, and Confirm confirms" \
  /usr/bin/python3 "$here/support/chromium_page.py" confirm "http://127.0.0.1:$http_port/" \
  'boss:admin-secret-3'
check "the applied file stays, with no window left open" \
  bash -c "head -1 '$dir/plant.toml' | grep -q '^# edited through the page' && ! test -e '$dir/plant.toml.pending'"
[ "$failures" = 0 ] || { echo "gateway log:"; tail -20 "$dir/gateway.err"; }
echo "$passes passed, $failures failed"
[ "$failures" = 0 ]
