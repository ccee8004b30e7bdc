#!/usr/bin/env bash
# From the box to a configuration: `tiltgate scan --config-out` against `tiltgate sim rieker`
# writes a configuration of the sensors it found, each with its serial, `tiltgate check` accepts
# it, and `tiltgate info` reaches each sensor through it. A second scan refuses to overwrite it
# without --force. A relative --device is written relative to the new file.
set -u
tiltgate=${1:?usage: scan_config_out_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-scan-config-out

start_sim "$tiltgate" rieker h6:223,h4360:101 "$dir/ttyRieker"
config="$dir/found.toml"

check "scan writes the configuration" \
  "$tiltgate" scan --port "$dir/ttyRieker" --config-out "$config"
check "the configuration has one bus and both sensors, numbered from unit id 1" \
  bash -c "grep -c '^\[\[bus\]\]' '$config' | grep -qx 1 &&
           grep -q '^name = \"sensor_101\"' '$config' && grep -q '^name = \"sensor_223\"' '$config' &&
           grep -q '^model = \"h4360\"' '$config' &&
           grep -q '^unit_id = 1 ' '$config' && grep -q '^unit_id = 2 ' '$config'"
check "each sensor has the serial it reported as its serial key" \
  bash -c "grep -q '^serial = \"9600223\" ' '$config' && grep -q '^serial = \"9600101\" ' '$config'"
check "tiltgate check accepts it" "$tiltgate" check --config "$config"
check "info reaches a sensor through it" \
  bash -c "'$tiltgate' info --config '$config' --sensor sensor_223 | grep -q '^serial:     9600223$'"

# A second scan keeps the file unless told to overwrite it.
cp "$config" "$dir/first.toml"
"$tiltgate" scan --port "$dir/ttyRieker" --config-out "$config" >"$dir/again.out" 2>&1
check "a second scan without --force exits 2" test $? -eq 2
check "and leaves the file as it was" cmp -s "$config" "$dir/first.toml"
check "with --force it writes it again" \
  "$tiltgate" scan --port "$dir/ttyRieker" --config-out "$config" --force

# A device profile given relative (--device) is written relative to the new file, where the
# loader looks for it: the folder can move, or be copied to the gateway, with its profiles.
start_sim "$tiltgate" modbus-rtu modbus-rtu:1 "$dir/ttyRtu"
mkdir -p "$dir/plant/devices" "$dir/work"
cp "$(dirname "$0")/../../examples/devices/rtu-inclinometer.toml" "$dir/plant/devices/incl.toml"
check "scan of Modbus RTU devices with a relative --device writes a configuration" \
  bash -c "cd '$dir/work' && '$tiltgate' scan --port '$dir/ttyRtu' --protocol modbus-rtu \
             --to 2 --device ../plant/devices/incl.toml --config-out ../plant/rtu.toml"
check "its device path is relative to the file" \
  grep -qx 'device = "devices/incl.toml"' "$dir/plant/rtu.toml"
mv "$dir/plant" "$dir/moved"
check "tiltgate check accepts it from the folder's new place" \
  "$tiltgate" check --config "$dir/moved/rtu.toml"

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
