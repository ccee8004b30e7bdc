#!/usr/bin/env bash
# End to end: `tiltgate sim` takes commands on a piped standard input while it runs ("angle" for
# Rieker, "counts" for Spectron, "serial" for both: another sensor swapped in), answers each with
# "ok" or "error: ...", and the sensor answers the new value from then on, as `tiltgate raw` (or
# `info`) reads it. A terminal or /dev/null as standard
# input is not read.
set -u
tiltgate=${1:?usage: sim_commands_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-sim-commands

# The simulator reads the fifo; fd 3 is the test's end, kept open so the simulator sees no EOF.
mkfifo "$dir/commands"
"$tiltgate" sim rieker --sensors h6:223,h4360:101 --link "$dir/tty" <"$dir/commands" \
  >"$dir/sim.out" 2>"$dir/sim.err" &
pids+=($!)
exec 3>"$dir/commands"
check "the simulator started" wait_for_link "$dir/tty"
check "the simulator says it reads commands" grep -q "reading commands from standard input" "$dir/sim.err"

# send LINE: writes one command and prints its answer (waiting at most 5 s): the line after the
# answers so far (the simulator's first line is the pty's path).
send() {
  local before
  before=$(wc -l <"$dir/sim.out")
  echo "$1" >&3
  for _ in $(seq 100); do
    [ "$(wc -l <"$dir/sim.out")" -gt "$before" ] && break
    sleep 0.05
  done
  sed -n "$((before + 1))p" "$dir/sim.out"
}
# angles TTY ADDRESS TYPE: Get Angle of that type, as `tiltgate raw` shows it.
angles() { timeout 30 "$tiltgate" raw --port "$1" --protocol rieker --address "$2" --function 5 --data "$3" 2>&1; }

check "angle on an H6 answers ok" test "$(send "angle 223 12.5 -3.25")" = "ok"
angles "$dir/tty" 223 04 >"$dir/h6.out"
check "the H6 answers the new X" grep -qxF "angle x:  12.500 deg" "$dir/h6.out"
check "the H6 answers the new Y" grep -qxF "angle y:  -3.250 deg" "$dir/h6.out"
check "angle on an H4360 answers ok" test "$(send "angle 101 -45")" = "ok"
angles "$dir/tty" 101 01 >"$dir/h4360.out"
check "the H4360 answers the new angle" grep -qxF "angle x:  -45.000 deg" "$dir/h4360.out"

check "no sensor at the address is an error" \
  test "$(send "angle 7 1")" = "error: no sensor at address 7"
check "two angles for a single-axis sensor is an error" \
  test "$(send "angle 101 1 2")" = "error: the sensor at address 101 takes 1 angle(s)"
check "a word that is not a number is an error" test "$(send "angle 223 x")" = 'error: "x" is not a number'
check "an unknown command is an error naming the right ones" \
  test "$(send "tilt 223 1")" = 'error: unknown command "tilt" (try: angle ADDRESS X [Y], silent ADDRESS, garbage ADDRESS, late ADDRESS MS, busy ADDRESS, answer ADDRESS, serial ADDRESS NUMBER, unplug MASTER, replug MASTER)'
check "the simulator still answers after bad commands" test "$(send "angle 223 1 2")" = "ok"
check "serial on an H6 answers ok" test "$(send "serial 223 9600007")" = "ok"
check "the H6 reports the new serial, as a sensor swapped in would" \
  bash -c "timeout 30 '$tiltgate' info --port '$dir/tty' --protocol rieker --address 223 |
           grep -q '^serial:     9600007$'"
check "serial takes a whole number" \
  test "$(send "serial 223 1.5")" = "error: serial takes one whole number of at most 10 digits"

check "silent on an H6 answers ok" test "$(send "silent 223")" = "ok"
angles "$dir/tty" 223 04 >"$dir/silent.out"
check "the silent H6 gives no reply" grep -q "no reply" "$dir/silent.out"
check "silent takes only an address" test "$(send "silent 223 1")" = "error: silent takes only an address"
check "answer on the silent H6 answers ok" test "$(send "answer 223")" = "ok"
angles "$dir/tty" 223 04 >"$dir/answers.out"
check "the H6 answers again" grep -qxF "angle x:  1.000 deg" "$dir/answers.out"

check "garbage on an H6 answers ok" test "$(send "garbage 223")" = "ok"
angles "$dir/tty" 223 04 >"$dir/garbage.out"
check "its reply fails its CRC" grep -q "bad CRC" "$dir/garbage.out"
check "busy on an H6 answers ok" test "$(send "busy 223")" = "ok"
check "late takes milliseconds" test "$(send "late 223")" = "error: late takes a whole number of milliseconds, 0..60000"
check "late on an H6 answers ok" test "$(send "late 223 300")" = "ok"
check "answer undoes them all" test "$(send "answer 223")" = "ok"
angles "$dir/tty" 223 04 >"$dir/answers_again.out"
check "the H6 answers again, in time" grep -qxF "angle x:  1.000 deg" "$dir/answers_again.out"

# Spectron: counts.
mkfifo "$dir/dyna-commands"
"$tiltgate" sim spectron --sensors dyna:5 --link "$dir/dyna" <"$dir/dyna-commands" \
  >"$dir/dyna.out" 2>"$dir/dyna.err" &
pids+=($!)
exec 4>"$dir/dyna-commands"
wait_for_link "$dir/dyna"
echo "counts 5 40000" >&4
echo "counts 5 -1200" >&4
echo "serial 5 70000" >&4
echo "serial 5 777" >&4
for _ in $(seq 100); do [ "$(wc -l <"$dir/dyna.out")" -ge 5 ] && break; sleep 0.05; done
check "counts out of range is an error" grep -qxF "error: counts takes one whole number, -32768..32767" "$dir/dyna.out"
check "counts in range answers ok" test "$(sed -n 3p "$dir/dyna.out")" = "ok"
check "a serial past EEPROM 4's word is an error" grep -qxF "error: serial takes one whole number, 0..65535" "$dir/dyna.out"
check "serial on a Dyna answers ok" test "$(sed -n 5p "$dir/dyna.out")" = "ok"
check "the Dyna reports the new serial, as a module swapped in would" \
  bash -c "timeout 30 '$tiltgate' info --port '$dir/dyna' --protocol spectron-9bit --baud 28800 \
             --address 5 | grep -q '^serial:     777$'"

# Standard input from /dev/null: not read, and the simulator runs as before.
"$tiltgate" sim rieker --sensors h6:223 --link "$dir/quiet" </dev/null >"$dir/quiet.out" 2>"$dir/quiet.err" &
pids+=($!)
wait_for_link "$dir/quiet"
check "with /dev/null the simulator serves" grep -qF "angle x:" <(angles "$dir/quiet" 223 04)
check "with /dev/null it does not say it reads commands" bash -c "! grep -q 'reading commands' '$dir/quiet.err'"

exec 3>&- 4>&-
echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
