#!/bin/bash
# `tiltgate check` refuses what it can know will fail on this machine (issue 52, item 7;
# docs/configuration.md, "What check asks of the machine"): a [server] user that does not
# exist, a listen address no interface has, TLS files that are not a certificate and its key;
# and its errors never show a file that is not TOML (a map file must be named *.toml).
# Certificates from the openssl CLI. Usage: check_machine_test.sh path/to/tiltgate
set -u
tiltgate=$1
. "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-check-machine
require_command openssl openssl

make_pair() {
  openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 2 \
    -subj "/CN=$1" -keyout "$dir/$1.key" -out "$dir/$1.pem" 2>>"$dir/openssl.log"
}
make_pair gateway
make_pair other
# A file the service can read that is no business of an admin's: its words must never show.
printf 'root:SECRET-HASH-1:19000:0:99999:7:::\nSECRET-LINE-2 = "x"\n' >"$dir/secret"
cp "$dir/secret" "$dir/secret.txt"

# write NAME [SERVER_LINES] [HTTP_LINES]: a configuration of one H6 on a tty that need not exist.
write() {
  one_h6_config 5020 /dev/null "${2:-}" | sed "s|^enabled = false|enabled = ${3:-false}|" \
    >"$dir/$1.toml"
}
# refused NAME TEXT: check exits 1 and says TEXT, and shows nothing of the secret file.
refused() {
  "$tiltgate" check --config "$dir/$1.toml" >"$dir/$1.out" 2>&1
  local code=$?
  [ "$code" = 1 ] && grep -qF -- "$2" "$dir/$1.out" && ! grep -q SECRET "$dir/$1.out" \
    || { echo "exit $code:"; cat "$dir/$1.out"; return 1; }
}
passes_check() { "$tiltgate" check --config "$dir/$1.toml"; }

write good 'tls = { cert = "gateway.pem", key = "gateway.key", ca = "other.pem", port = 8802 }'
check "a certificate with its key passes" passes_check good

write no_user 'user = "nosuchuser-tiltgate"'
check "a [server] user that does not exist is refused" \
  refused no_user 'server.user: no user "nosuchuser-tiltgate" on this machine'

# TEST-NET-3 and TEST-NET-1 addresses: no interface of this machine has them.
write modbus_away 'listen = "203.0.113.7"'
sed -i '0,/^listen = "127.0.0.1"/{//d}' "$dir/modbus_away.toml"
check "a [server] listen address this machine does not have is refused" \
  refused modbus_away 'server.listen: no interface of this machine has the address 203.0.113.7'

write console_away '' true
sed -i 's|^enabled = true|enabled = true\nlisten = "192.0.2.1"|' "$dir/console_away.toml"
check "an [http] listen address this machine does not have is refused" \
  refused console_away 'http.listen: no interface of this machine has the address 192.0.2.1'

write wrong_key 'tls = { cert = "gateway.pem", key = "other.key", ca = "other.pem", port = 8802 }'
check "a key that is not the certificate's is refused" \
  refused wrong_key "the key in $dir/other.key is not the key of the certificate in $dir/gateway.pem"

write not_cert 'tls = { cert = "secret", key = "gateway.key", ca = "other.pem", port = 8802 }'
check "a file that holds no certificate is refused, unquoted" \
  refused not_cert "$dir/secret holds no PEM certificate"

write not_key 'tls = { cert = "gateway.pem", key = "secret", ca = "other.pem", port = 8802 }'
check "a file that holds no key is refused, unquoted" \
  refused not_key "$dir/secret holds no unencrypted PEM private key"

write console_cert '' true
sed -i "s|^enabled = true|enabled = true\ntls_cert_file = \"secret\"\ntls_key_file = \"gateway.key\"|" \
  "$dir/console_cert.toml"
check "an [http] tls_cert_file that holds no certificate is refused, unquoted" \
  refused console_cert "http.tls_cert_file: $dir/secret holds no PEM certificate"

for name in secret secret.txt; do
  write "map_$name"
  printf 'map = "%s"\n' "$name" >>"$dir/map_$name.toml"
  check "a map file named $name is not read as TOML, and nothing of it is shown" \
    refused "map_$name" "is not named *.toml"
done

echo "$passes passed, $failures failed"
[ "$failures" = 0 ]
