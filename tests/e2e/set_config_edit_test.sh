#!/usr/bin/env bash
# End to end: `tiltgate set --config FILE --sensor NAME` re-addresses a simulated sensor from
# its factory address 223 to 7 and a new baud rate, and writes both into the configuration file
# in place: `tiltgate check` accepts the file, `diff` shows only the changed lines, with every
# comment (and the sensor's serial) kept, and `tiltgate info` finds the sensor through the file
# at its new address.
set -u
tiltgate=${1:?usage: set_config_edit_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-set-config
start_sim "$tiltgate" rieker h6:223,h4360:101 "$dir/tty"

cat >"$dir/plant.toml" <<TOML
# Plant line 1: the boom's sensors.
[[bus]]
name = "line1"          # RS485 on the cabinet's adapter
port = "$dir/tty"

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223           # factory address, change on site
unit_id = 1
serial = "9600223"      # the sensor's own: another at its address is not served as it
mounting = { swap_axes = false, rotate_deg = 0 }

[[sensor]]
name = "mast"
bus = "line1"
model = "h4360"
address = 101
unit_id = 2
TOML
cp "$dir/plant.toml" "$dir/before.toml"

# 1. A new address: one line changes, its comment kept.
"$tiltgate" set --config "$dir/plant.toml" --sensor boom address 7 >"$dir/set.out" 2>&1
check "set address exits 0" test $? -eq 0
check "set says it updated the file" \
  grep -qxF "updated $dir/plant.toml: sensor boom address 223 -> 7" "$dir/set.out"
check "tiltgate check accepts the edited file" "$tiltgate" check --config "$dir/plant.toml"
diff "$dir/before.toml" "$dir/plant.toml" >"$dir/address.diff"
cat >"$dir/address.expected" <<'DIFF'
10c10
< address = 223           # factory address, change on site
---
> address = 7           # factory address, change on site
DIFF
check "diff shows only the address line" diff "$dir/address.expected" "$dir/address.diff"
check "info finds the sensor through the file at 7" \
  "$tiltgate" info --config "$dir/plant.toml" --sensor boom

# 2. A new baud rate: the bus had none, so one line is added under its name.
cp "$dir/plant.toml" "$dir/before-baud.toml"
"$tiltgate" set --config "$dir/plant.toml" --sensor boom baud 115200 >"$dir/baud.out" 2>&1
check "set baud exits 0" test $? -eq 0
check "set says it added the bus's baud" \
  grep -qxF "updated $dir/plant.toml: bus line1 baud (not given) -> 115200" "$dir/baud.out"
check "tiltgate check accepts the file with the added baud" \
  "$tiltgate" check --config "$dir/plant.toml"
diff "$dir/before-baud.toml" "$dir/plant.toml" >"$dir/baud.diff"
cat >"$dir/baud.expected" <<'DIFF'
3a4
> baud = 115200
DIFF
check "diff shows only the added baud line" diff "$dir/baud.expected" "$dir/baud.diff"

# 3. A taken address: refused, the file untouched.
cp "$dir/plant.toml" "$dir/before-taken.toml"
"$tiltgate" set --config "$dir/plant.toml" --sensor boom address 101 >"$dir/taken.out" 2>&1
check "set to a taken address exits 1" test $? -eq 1
check "the file is unchanged after a refusal" cmp "$dir/before-taken.toml" "$dir/plant.toml"

check "set kept the sensor's serial" grep -q '^serial = "9600223" ' "$dir/plant.toml"

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
