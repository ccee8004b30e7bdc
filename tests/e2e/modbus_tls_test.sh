#!/usr/bin/env bash
# Modbus/TCP Security end to end: a CA, the gateway's and clients' certificates made here with
# the openssl CLI, `tiltgate run` with [server] tls on a simulated Rieker bus, and a Python
# `ssl` client (stdlib) reading registers. A client without a certificate, or with one another
# CA signed, is refused; plain TCP still works beside TLS, and is off with plain_tcp = false.
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
make_ca plant-ca && make_ca other-ca &&
  make_cert gateway plant-ca "subjectAltName=IP:127.0.0.1
extendedKeyUsage=serverAuth" &&
  make_cert plc plant-ca "extendedKeyUsage=clientAuth" &&
  make_cert intruder other-ca "extendedKeyUsage=clientAuth" ||
  { echo "FAIL: openssl could not make the certificates"; cat "$dir/openssl.log"; exit 1; }

# read_registers PORT [CERT]: reads input registers 0-1 of unit 1 over TLS (with the client
# certificate CERT, or none) checking the gateway's certificate against plant-ca; PORT plain:N
# reads over plain TCP. Exit 0: answered with function 04; 2: refused or closed; 1: otherwise.
read_registers() {
  (cd "$dir" && /usr/bin/python3 - "$@") <<'PY'
import socket, ssl, struct, sys
target, cert = sys.argv[1], (sys.argv[2] if len(sys.argv) > 2 else None)
plain = target.startswith("plain:")
port = int(target.split(":")[-1])
request = struct.pack(">HHHBBHH", 1, 0, 6, 1, 0x04, 0, 2)
try:
    sock = socket.create_connection(("127.0.0.1", port), timeout=5)
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
sys.exit(0 if reply[7] == 0x04 else 1)
PY
}
refused() { read_registers "$@"; [ $? -eq 2 ]; }

start_sim "$tiltgate" rieker h6:223 "$dir/ttyUSB0"
port=$(free_port)
tls_port=$(free_port)
while [ "$tls_port" = "$port" ]; do tls_port=$(free_port); done

# write_config PLAIN_TCP: the plant with TLS, relative paths (resolved against the file's folder).
write_config() {
  cat >"$dir/plant.toml" <<TOML
[server]
listen = "127.0.0.1"
port = $port
plain_tcp = $1
tls = { cert = "gateway.pem", key = "gateway.key", ca = "plant-ca.pem", port = $tls_port }

[http]
enabled = false

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
kill "$gateway"
wait "$gateway" 2>/dev/null

write_config false
start_gateway
check "with plain_tcp = false nothing listens on the plain port" refused "plain:$port"
check "with plain_tcp = false TLS is served" read_registers "$tls_port" plc

echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]
