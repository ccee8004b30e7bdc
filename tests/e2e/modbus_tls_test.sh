#!/usr/bin/env bash
# Modbus/TCP Security end to end: a CA, the gateway's and clients' certificates made here with
# the openssl CLI, `tiltgate run` with [server] tls on a simulated Rieker bus, and a Python
# `ssl` client (stdlib) reading and writing registers. A client without a certificate, or with
# one another CA signed, is refused; plain TCP still works beside TLS, and is off with
# plain_tcp = false. The authorization step: a certificate's role (its RoleOID extension) is
# read-only or read-write as [server] tls_role_access says, a role it does not name read-only,
# and a certificate without one as tls_no_role_access says (default read-write).
set -u
tiltgate=${1:?usage: modbus_tls_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-tls
for tool in openssl /usr/bin/python3; do
  command -v "$tool" >/dev/null && continue
  echo "FAIL: $tool not found (Debian packages openssl, python3). Run scripts/setup."
  echo "0 passed, 1 failed"
  exit 1
done

# make_ca NAME; make_cert NAME CA EXTENSION: EC P-256 keys, valid for two days.
make_ca() {
  openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 2 \
    -subj "/CN=$1" -keyout "$dir/$1.key" -out "$dir/$1.pem" 2>>"$dir/openssl.log"
}
make_cert() {
  openssl req -new -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -subj "/CN=$1" \
    -keyout "$dir/$1.key" -out "$dir/$1.csr" 2>>"$dir/openssl.log" &&
  printf '%s\n' "$3" >"$dir/$1.ext" &&
  openssl x509 -req -in "$dir/$1.csr" -CA "$dir/$2.pem" -CAkey "$dir/$2.key" -CAcreateserial \
    -days 2 -extfile "$dir/$1.ext" -out "$dir/$1.pem" 2>>"$dir/openssl.log"
}
# with_role ROLE: a client certificate's extensions with Modbus/TCP Security's role extension.
with_role() {
  printf 'extendedKeyUsage=clientAuth\n1.3.6.1.4.1.50316.802.1=ASN1:UTF8String:%s' "$1"
}
make_ca plant-ca && make_ca other-ca &&
  make_cert gateway plant-ca "subjectAltName=IP:127.0.0.1
extendedKeyUsage=serverAuth" &&
  make_cert plc plant-ca "extendedKeyUsage=clientAuth" &&
  make_cert intruder other-ca "extendedKeyUsage=clientAuth" &&
  make_cert engineer plant-ca "$(with_role engineer)" &&
  make_cert operator plant-ca "$(with_role operator)" &&
  make_cert visitor plant-ca "$(with_role visitor)" ||
  { echo "FAIL: openssl could not make the certificates"; cat "$dir/openssl.log"; exit 1; }

# modbus_request read|write PORT [CERT]: reads input registers 0-1 of unit 1, or writes 3 to its
# holding register 0 (the filter), over TLS (with the client certificate CERT, or none)
# checking the gateway's certificate against plant-ca; PORT plain:N goes over plain TCP. From
# $SOURCE (default 127.0.0.1), another loopback address to be another host. Exit 0: answered
# with the function asked (04, 06); 3: exception 01; 2: refused or closed; 1: otherwise.
modbus_request() {
  (cd "$dir" && SOURCE=${SOURCE:-127.0.0.1} /usr/bin/python3 - "$@") <<'PY'
import os, socket, ssl, struct, sys
mode, target = sys.argv[1], sys.argv[2]
cert = sys.argv[3] if len(sys.argv) > 3 else None
plain = target.startswith("plain:")
port = int(target.split(":")[-1])
function = 0x04 if mode == "read" else 0x06
request = struct.pack(">HHHBBHH", 1, 0, 6, 1, function, 0, 2 if mode == "read" else 3)
try:
    sock = socket.create_connection(("127.0.0.1", port), timeout=5,
                                    source_address=(os.environ["SOURCE"], 0))
    if not plain:
        context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
        context.load_verify_locations("plant-ca.pem")
        if cert:
            context.load_cert_chain(cert + ".pem", cert + ".key")
        sock = context.wrap_socket(sock, server_hostname="127.0.0.1")
    sock.sendall(request)
    reply = b""
    while len(reply) < 9:
        chunk = sock.recv(64)
        if not chunk:
            break
        reply += chunk
except (OSError, ssl.SSLError) as e:
    print("refused:", e)
    sys.exit(2)
print("reply:", reply.hex())
if len(reply) < 9:
    sys.exit(2)
if reply[7] == function | 0x80 and reply[8] == 0x01:
    sys.exit(3)
sys.exit(0 if reply[7] == function else 1)
PY
}
read_registers() { modbus_request read "$@"; }
refused() { read_registers "$@"; [ $? -eq 2 ]; }
write_register() { modbus_request write "$@"; }
write_refused_01() { write_register "$@"; [ $? -eq 3 ]; }
# metric NAME VALUE: the gateway's /metrics has NAME at VALUE.
metric() {
  /usr/bin/python3 -c 'import sys, urllib.request
text = urllib.request.urlopen(sys.argv[1], timeout=5).read().decode()
sys.exit(0 if sys.argv[2] + " " + sys.argv[3] + "\n" in text else 1)' \
    "http://127.0.0.1:$http_port/metrics" "$1" "$2"
}

start_sim "$tiltgate" rieker h6:223 "$dir/ttyUSB0"
port=$(free_port)
tls_port=$(free_port)
http_port=$(free_port)

# write_config PLAIN_TCP [SERVER-KEYS]: the plant with TLS, relative paths (resolved against the
# file's folder), writes on, and SERVER-KEYS added to [server].
write_config() {
  cat >"$dir/plant.toml" <<TOML
[server]
listen = "127.0.0.1"
port = $port
plain_tcp = $1
tls = { cert = "gateway.pem", key = "gateway.key", ca = "plant-ca.pem", port = $tls_port }
writes = true
${2:-}
state_dir = "$dir/state"

[http]
listen = "127.0.0.1"
port = $http_port

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
TOML
}

# start_gateway: runs it and waits (at most 10 s) until the PLC's certificate reads over TLS.
start_gateway() {
  "$tiltgate" run --config "$dir/plant.toml" 2>"$dir/gateway.err" &
  gateway=$!
  pids+=($gateway)
  for _ in $(seq 200); do
    read_registers "$tls_port" plc >/dev/null 2>&1 && return 0
    sleep 0.05
  done
  echo "FAIL: the gateway did not serve Modbus over TLS"
  cat "$dir/gateway.err"
  exit 1
}

write_config true
start_gateway
check "a client with a certificate the plant CA signed reads registers over TLS" \
  read_registers "$tls_port" plc
check "a client without a certificate is refused" refused "$tls_port"
check "a client whose certificate another CA signed is refused" refused "$tls_port" intruder
check "plain TCP still works beside TLS" read_registers "plain:$port"
check "a plain Modbus client on the TLS port gets no answer" refused "plain:$tls_port"
check "the refused handshakes are logged" grep -q "TLS handshake failed" "$dir/gateway.err"
# tls12_suite SUITE: a TLS 1.2 handshake offering only SUITE (with the PLC's certificate) ends
# with that suite (docs/operations.md, "Modbus/TCP Security": AEAD suites only).
tls12_suite() {
  openssl s_client -connect "127.0.0.1:$tls_port" -tls1_2 -cipher "$1" -cert "$dir/plc.pem" \
    -key "$dir/plc.key" </dev/null >"$dir/s_client.out" 2>&1 &&
    grep -q "Cipher is $1" "$dir/s_client.out"
}
# tls12_refused SUITE: the gateway ends that handshake with a handshake failure alert (the
# client offered the suite: it is the server that has none in common).
tls12_refused() {
  ! tls12_suite "$1" && grep -q "alert handshake failure" "$dir/s_client.out"
}
check "TLS 1.2 with an AEAD suite (ECDHE-ECDSA-AES128-GCM-SHA256) is accepted" \
  tls12_suite ECDHE-ECDSA-AES128-GCM-SHA256
check "TLS 1.2 with a CBC-SHA1 suite (ECDHE-ECDSA-AES128-SHA) is refused" \
  tls12_refused ECDHE-ECDSA-AES128-SHA
check "TLS 1.2 with a CBC-SHA256 suite (ECDHE-ECDSA-AES128-SHA256) is refused" \
  tls12_refused ECDHE-ECDSA-AES128-SHA256
check "the PLC still reads over TLS after the refused suites" read_registers "$tls_port" plc
kill "$gateway"
wait "$gateway" 2>/dev/null

# The authorization step: roles from the certificates' role extension.
write_config true 'tls_role_access = { engineer = "read-write", operator = "read-only" }'
start_gateway
check "an engineer's certificate (role read-write) writes" write_register "$tls_port" engineer
check "an operator's certificate (role read-only) reads" read_registers "$tls_port" operator
check "an operator's certificate's write is refused with 01" write_refused_01 "$tls_port" operator
check "a certificate without a role writes (tls_no_role_access defaults to read-write)" \
  write_register "$tls_port" plc
SOURCE=127.0.0.3
check "a role the table does not name reads" read_registers "$tls_port" visitor
check "a role the table does not name may only read: its write is refused with 01" \
  write_refused_01 "$tls_port" visitor
SOURCE=
check "the unknown role is logged with the certificate's subject" \
  grep -q 'client 127\.0\.0\.3:[0-9]* (CN=visitor): its certificate.s role "visitor" is not in \[server\] tls_role_access: read-only' \
  "$dir/gateway.err"
check "a refused write is logged with the client's certificate subject and role" \
  grep -q 'client 127\.0\.0\.1:[0-9]* (CN=operator): function 06 refused with 01: its certificate.s role "operator" may only read' \
  "$dir/gateway.err"
check "the refused writes count as writes denied" metric tiltgate_modbus_writes_denied_total 2
check "plain TCP writes beside TLS" write_register "plain:$port"
check "the audit trail names a TLS client by its address and its certificate's subject" \
  grep -q '127\.0\.0\.1:[0-9]* (CN=engineer)' <("$tiltgate" audit --state-dir "$dir/state" --door modbus)

# tls_no_role_access = "read-only", applied by a reload: certificates without a role only read.
write_config true 'tls_role_access = { engineer = "read-write", operator = "read-only" }
tls_no_role_access = "read-only"'
kill -HUP "$gateway"
for _ in $(seq 200); do
  write_refused_01 "$tls_port" plc >/dev/null 2>&1 && break
  sleep 0.05
done
check "with tls_no_role_access = read-only a certificate without a role has its write refused" \
  write_refused_01 "$tls_port" plc
check "with tls_no_role_access = read-only a certificate without a role reads" \
  read_registers "$tls_port" plc
check "and the engineer still writes" write_register "$tls_port" engineer
kill "$gateway"
wait "$gateway" 2>/dev/null

# Mistakes in the keys stop `tiltgate check` at their line.
bad_config() {
  write_config true "$1"
  ! "$tiltgate" check --config "$dir/plant.toml" >"$dir/check.out" 2>&1 &&
    grep -q "$2" "$dir/check.out"
}
check "an access other than read-only or read-write is an error at its line" bad_config \
  'tls_role_access = { operator = "readonly" }' \
  'plant.toml:7.*tls_role_access.operator.*"readonly" is not valid; did you mean "read-only"'
check "tls_no_role_access other than read-only or read-write is an error at its line" bad_config \
  'tls_no_role_access = "none"' 'plant.toml:7.*tls_no_role_access.*"none" is not valid'

write_config false
start_gateway
check "with plain_tcp = false nothing listens on the plain port" refused "plain:$port"
check "with plain_tcp = false TLS is served" read_registers "$tls_port" plc

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
