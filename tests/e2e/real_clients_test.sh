#!/usr/bin/env bash
# End to end with the clients a controls engineer uses: mbpoll (Debian's package) and
# pymodbus (Debian's python3-pymodbus), against `tiltgate run` on a simulated Rieker bus
# served by `tiltgate sim rieker` in another process. A missing client is a failure, never a
# skip: scripts/setup installs both.
set -u
tiltgate=${1:?usage: real_clients_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-clients
# Python runs in the scratch directory: from the source tree, the serial/ folder would shadow
# the serial module pymodbus imports.
py() { (cd "$dir" && /usr/bin/python3 - "$@"); }

# Exactly what the clients below import, so a missing module names its Debian package.
clients_missing=""
command -v mbpoll >/dev/null || clients_missing+="mbpoll not found (Debian package mbpoll). "
if [ ! -x /usr/bin/python3 ]; then
  clients_missing+="/usr/bin/python3 not found (Debian package python3). "
elif ! py >"$dir/imports.out" 2>&1 <<'PY'
import importlib, sys
packages = {"pymodbus": "python3-pymodbus", "serial_asyncio": "python3-serial-asyncio",
            "serial": "python3-serial"}
for module in ("pymodbus.client", "pymodbus.mei_message"):
    try:
        importlib.import_module(module)
    except ModuleNotFoundError as e:
        top = (e.name or "").split(".")[0]
        sys.exit(f"import {module}: no module named {e.name!r} "
                 f"(Debian package {packages.get(top, 'unknown')})")
PY
then
  clients_missing+="$(tail -1 "$dir/imports.out"). "
fi
if [ -n "$clients_missing" ]; then
  echo "FAIL: the real clients are not installed: ${clients_missing}Run scripts/setup."
  echo "0 passed, 1 failed"
  exit 1
fi

start_sim "$tiltgate" rieker h6:223,h4360:101,h6:224 "$dir/ttyUSB0"
port=$(free_port)
cp "$(dirname "$0")/../../examples/maps/cdab-floats.toml" "$dir/cdab-floats.toml"
cat >"$dir/plant.toml" <<TOML
[server]
listen = "127.0.0.1"
port = $port
writes = true

[[bus]]
name = "line1"
port = "$dir/ttyUSB0"
protocol = "rieker"
timeout_ms = 100

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
unit_id = 1
poll_ms = 50

[[sensor]]
name = "mast"
bus = "line1"
model = "h4360"
address = 101
unit_id = 2
poll_ms = 50

[[sensor]]
name = "jib"
bus = "line1"
model = "h6"
address = 224
unit_id = 3
poll_ms = 50
map = "cdab-floats.toml"
TOML
"$tiltgate" run --config "$dir/plant.toml" 2>"$dir/gateway.err" &
pids+=($!)
ready=""
for _ in $(seq 200); do
  if mbpoll -m tcp -p "$port" -a 1 -t 3:float -B -r 1 -c 2 -1 -o 1 127.0.0.1 >"$dir/first.out" 2>&1; then
    ready=yes; break
  fi
  sleep 0.05
done
[ -n "$ready" ] || { echo "gateway did not serve angles"; cat "$dir/gateway.err" "$dir/first.out"; exit 1; }

mb() { mbpoll -m tcp -p "$port" -1 -o 2 "$@" 127.0.0.1; }
mbw() { local value=$1; shift; mbpoll -m tcp -p "$port" -1 -o 2 "$@" 127.0.0.1 "$value"; }

# The spec parser gives sensor i the angles X = 1 + i, Y = -(1 + i), swaying by 0.25 degrees.
angles_ok() {
  mb -a 1 -t 3:float -B -r 1 -c 2 | awk '/^\[1\]:/ {x=$2} /^\[3\]:/ {y=$2}
    END {exit !(x > 0.7 && x < 1.3 && y < -0.7 && y > -1.3)}'
}
check "mbpoll reads the H6 angles as big-endian floats" angles_ok
# Unit 3 uses examples/maps/cdab-floats.toml: mbpoll's default word order is CDAB (no -B).
cdab_ok() {
  mb -a 3 -t 3:float -r 1 -c 2 | awk '/^\[1\]:/ {x=$2} /^\[3\]:/ {y=$2}
    END {exit !(x > 2.7 && x < 3.3 && y < -2.7 && y > -3.3)}'
}
check "mbpoll reads a CDAB map file's floats in its own default word order" cdab_ok
serial_ok() { mb -a 1 -t 3:hex -r 17 -c 5 | grep -q '^\[17\]:.*0x3936'; }
check "mbpoll reads the serial number string" serial_ok
online_ok() { mb -a 2 -t 1 -r 1 | grep -q '^\[1\]:.*1'; }
check "mbpoll reads the online discrete input" online_ok
write_ok() { mbw 2 -a 1 -t 4 -r 1 && mb -a 1 -t 4 -r 1 | grep -q '^\[1\]:.*2'; }
check "mbpoll writes the filter and reads it back" write_ok
bad_value() { ! mbw 9 -a 1 -t 4 -r 1 && mbw 9 -a 1 -t 4 -r 1 2>&1 | grep -qi "illegal data value"; }
check "mbpoll sees exception 0x03 for filter 9" bad_value
unknown_unit() { mb -a 9 -t 3 -r 1 -c 2 2>&1 | grep -qi "gateway path"; }
check "mbpoll sees exception 0x0A for an unknown unit" unknown_unit

pymodbus_ok() {
  py "$port" <<'PY'
import struct, sys
from pymodbus.client import ModbusTcpClient
client = ModbusTcpClient("127.0.0.1", port=int(sys.argv[1]), timeout=3)
assert client.connect()
r = client.read_input_registers(0, 2, slave=2)
assert not r.isError(), r
x = struct.unpack(">f", struct.pack(">HH", *r.registers))[0]
assert 1.7 < x < 2.3, x
r = client.read_input_registers(1, 2, slave=2)
assert r.isError() and r.exception_code == 2, r
client.close()
PY
}
check "pymodbus reads the H4360 angle and sees exception 0x02 for a split float" pymodbus_ok
# The README's function 43 recipe, as written there, for Debian 12's pymodbus 3.0 (which has
# no read_device_information(), and ignores slave= on a request object: the unit is unit=).
device_identification_ok() {
  py "$port" <<'PY'
import sys
from pymodbus.client import ModbusTcpClient
from pymodbus.mei_message import ReadDeviceInformationRequest

client = ModbusTcpClient("127.0.0.1", port=int(sys.argv[1]))
client.connect()
reply = client.execute(ReadDeviceInformationRequest(read_code=0x01, object_id=0x00, unit=2))
print(reply.information)   # {0: b'Rieker Inc.', 1: b'H4360', 2: b'Rev ...'}
assert not reply.isError(), reply
assert reply.information[0] == b"Rieker Inc.", reply.information
assert reply.information[1] == b"H4360", reply.information
reply = client.execute(ReadDeviceInformationRequest(read_code=0x01, object_id=0x00, unit=1))
assert reply.information[1] == b"H6", reply.information
client.close()
PY
}
check "pymodbus reads VendorName with the README's function 43 recipe" device_identification_ok

# Function 08 and 11 (docs/diagnostics.md), as docs/diagnostics.md has pymodbus ask them.
diagnostics_ok() {
  py "$port" <<'PY'
import sys
from pymodbus.client import ModbusTcpClient
from pymodbus.diag_message import (ClearCountersRequest, ReturnQueryDataRequest,
                                   ReturnSlaveMessageCountRequest,
                                   ReturnSlaveNoResponseCountRequest)
from pymodbus.other_message import GetCommEventCounterRequest

client = ModbusTcpClient("127.0.0.1", port=int(sys.argv[1]), timeout=3)
assert client.connect()
echo = client.execute(ReturnQueryDataRequest(0x1234, unit=1))
assert not echo.isError(), echo
print("echo", echo.message)
assert list(echo.message) == [0x1234], echo.message
sent = client.execute(ReturnSlaveMessageCountRequest(unit=1))
assert not sent.isError(), sent
print("server messages", sent.message)
assert sent.message[0] > 0, sent.message
silent = client.execute(ReturnSlaveNoResponseCountRequest(unit=1))
assert not silent.isError() and silent.message[0] == 0, silent.message
events = client.execute(GetCommEventCounterRequest(unit=1))
assert not events.isError(), events
assert events.status and events.count > 0, (events.status, events.count)
cleared = client.execute(ClearCountersRequest(unit=1))
assert not cleared.isError(), cleared
after = client.execute(ReturnSlaveMessageCountRequest(unit=1))
assert after.message[0] < sent.message[0], (after.message, sent.message)
client.close()
PY
}
check "pymodbus asks 08 (echo, counts, clear) and 11" diagnostics_ok

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
