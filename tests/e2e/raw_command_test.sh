#!/usr/bin/env bash
# End to end: `tiltgate raw` against `tiltgate sim rieker` on a pseudo-terminal, as an engineer
# runs it from a shell: Get Serial's exact frames with the CRC verdict, a NAK's meaning with
# exit 1, silence with exit 1, bad data with exit 2.
set -u
tiltgate=${1:?usage: raw_command_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-raw
start_sim "$tiltgate" rieker h6:223,h4360:101 "$dir/tty"
raw() { timeout 30 "$tiltgate" raw --port "$dir/tty" --protocol rieker "$@"; }

raw --address 223 --function 37 >"$dir/serial.out" 2>&1
check "Get Serial exits 0" test $? -eq 0
check "the request's bytes are shown" grep -qxF "sent:     00 DF 00 00 00 25 00 FF 09" "$dir/serial.out"
check "the reply's bytes and CRC verdict are shown" grep -q "^received: 00 00 00 DF 00 25 0A .* (CRC ok)$" "$dir/serial.out"
check "the reply is decoded" grep -qxF "serial:   9600223" "$dir/serial.out"

raw --address 101 --function 5 --data 04 >"$dir/nak.out" 2>&1
check "a NAK exits 1" test $? -eq 1
check "a NAK is shown with its meaning" \
  grep -qxF "reply:    NAK 2 (function not valid for this sensor or mode)" "$dir/nak.out"

raw --address 9 --function 37 >"$dir/silent.out" 2>&1
check "silence exits 1" test $? -eq 1
check "silence says so, with the hint" grep -q "^hint:" "$dir/silent.out"

raw --address 223 --function 37 --data 1 >"$dir/bad.out" 2>&1
check "odd hex digits exit 2" test $? -eq 2

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
