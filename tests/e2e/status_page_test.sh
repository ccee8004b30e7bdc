#!/usr/bin/env bash
# The status page in Debian's headless Chromium: `tiltgate demo` serves it, every sensor's card
# shows an angle, the angles change while the page stays open, and when the gateway is killed
# the page says "gateway unreachable since ...". A missing chromium fails, never skips.
# Usage: status_page_test.sh path/to/tiltgate
set -u
tiltgate=${1:?usage: $0 path/to/tiltgate}
here=$(cd "$(dirname "$0")" && pwd)
source "$here/support/script_lib.sh"
script_setup tiltgate-page

if ! command -v chromium >/dev/null; then
  echo "FAIL: chromium not found (Debian package chromium). Run scripts/setup."
  exit 1
fi

port=$(free_port)
http_port=$(free_port)
"$tiltgate" demo --port "$port" --http-port "$http_port" --no-accounts >"$dir/demo.out" 2>"$dir/demo.err" &
demo=$!
pids+=($demo)
for _ in $(seq 150); do
  /usr/bin/python3 -c "import urllib.request as u; u.urlopen('http://127.0.0.1:$http_port/healthz', timeout=1)" \
    2>/dev/null && break
  sleep 0.1
done

/usr/bin/python3 "$here/support/chromium_page.py" check "http://127.0.0.1:$http_port/" "$demo"
result=$?
{ wait "$demo"; } 2>/dev/null  # killed by the check
if [ $result -eq 0 ]; then
  echo "1 passed, 0 failed"
else
  echo "demo log:"; tail -20 "$dir/demo.err"
  echo "0 passed, 1 failed"
  exit 1
fi
