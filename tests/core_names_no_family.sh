#!/usr/bin/env bash
# No folder but the families' own names a sensor family: the core (config/, mapping/, gateway/, line_scheduling/,
# serial/, driver/) and the rooms beside it (modbus_tcp/, status/, http/, mqtt/, control/,
# commission/, app/, sparkplug/, settings/, console/, accounts/, audit/, store/, device_server/) ask the family descriptors
# (driver/family.h) instead, so a new family is its own folder plus one line in
# families/families.cmake. Checks the sources (C++ and CMake), comments included.
# Documents (docs/, README.md) are not sources: they name the families for the engineer.
# Usage: core_names_no_family.sh SOURCE_DIR
set -u
root=${1:?usage: $0 SOURCE_DIR}
cd "$root" || exit 2
pattern='rieker|spectron|dyna|h6|h4360|modbus[ _-]rtu|\brtu\b'
sources=(--include='*.h' --include='*.cpp' --include='CMakeLists.txt' --include='*.cmake')

# The pattern must find the families themselves, or this check proves nothing.
if ! grep -rqiE "$pattern" "${sources[@]}" rieker spectron modbus_rtu; then
  echo "the pattern '$pattern' finds nothing in the family folders: the check is broken"
  exit 2
fi

rooms=(config mapping gateway line_scheduling serial driver doors modbus_tcp status http mqtt control commission app sparkplug settings console accounts audit
       store device_server capture capture_cli redundancy)
hits=$(grep -rniE "$pattern" "${sources[@]}" "${rooms[@]}")
if [ -n "$hits" ]; then
  echo "core sources name a sensor family (move it into the family's descriptor):"
  echo "$hits"
  exit 1
fi
echo "${rooms[*]}: no sensor family named"
