#!/usr/bin/env bash
# The Debian package (packaging/, docs/operations.md "Install on a gateway"), made by cpack from
# the already-built tree of the binary under test (no second compile), then checked as a gateway
# would get it: its files and control fields (conffile, Depends computed by dpkg-shlibdeps,
# the version from CMake), the manual (README.md and every docs/ page and image, uncompressed,
# the README's links resolving in the installed tree), a stripped binary, lintian without
# errors, the service unit through systemd-analyze verify and security (exposure at most 2.5),
# the packaged binary's `check` on the packaged configuration (loopback, writes off, the
# configuration reference named where it is installed), the web console's certificate the
# postinst makes (its script run on a folder of the test's), and the bash completion.
# A missing tool fails the test: scripts/setup installs them all.
set -u
tiltgate=${1:?usage: package_test.sh path/to/build/tiltgate}
build=$(cd "$(dirname "$tiltgate")" && pwd)
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-package

for tool in cpack dpkg-deb dpkg-shlibdeps lintian systemd-analyze readelf file man /bin/kill; do
  command -v "$tool" >/dev/null && continue
  echo "FAIL: $tool not found (lintian, systemd, dpkg-dev, file, binutils, man-db, procps: run scripts/setup)"
  exit 1
done
version=$("$tiltgate" --version | sed -n 's/^tiltgate //p')

# cpack installs what build/ has built (packaging/package.cmake), into a folder of our own.
if ! (cd "$build" && cpack -G DEB -B "$dir/out") >"$dir/cpack.log" 2>&1; then
  echo "FAIL: cpack"; tail -20 "$dir/cpack.log"; exit 1
fi
deb="$dir/out/tiltgate_${version}_$(dpkg --print-architecture).deb"
if [ ! -f "$deb" ]; then
  echo "FAIL: no $deb"; ls "$dir/out"; exit 1
fi

contents=$(dpkg-deb -c "$deb" | awk '{print $NF}')
for file in ./usr/bin/tiltgate ./etc/tiltgate/tiltgate.toml ./lib/systemd/system/tiltgate.service \
            ./usr/share/man/man1/tiltgate.1.gz ./usr/share/bash-completion/completions/tiltgate \
            ./usr/share/doc/tiltgate/copyright ./usr/share/doc/tiltgate/changelog.gz \
            ./usr/share/doc/tiltgate/README.md ./usr/share/doc/tiltgate/docs/configuration.md \
            ./usr/share/doc/tiltgate/examples/tiltgate.toml \
            ./usr/share/doc/tiltgate/examples/maps/cdab-floats.toml \
            ./usr/share/doc/tiltgate/examples/devices/rtu-inclinometer.toml \
            ./usr/libexec/tiltgate/make-console-certificate ./usr/share/tiltgate/tiltgate.lua; do
  check "the package holds $file" grep -qx -- "$file" <<<"$contents"
done
# The manual: every page of docs/ and every image, under docs/ beside the README.
for page in "$source_dir"/docs/*.md "$source_dir"/docs/*.png; do
  check "the package holds the manual's docs/${page##*/}" \
    grep -qx -- "./usr/share/doc/tiltgate/docs/${page##*/}" <<<"$contents"
done
check "the package holds no CONFIG-REFERENCE.md (docs/configuration.md replaced it)" \
  bash -c '! grep -q CONFIG-REFERENCE' <<<"$contents"
field() { dpkg-deb -f "$deb" "$1"; }
check "Package: tiltgate" test "$(field Package)" = tiltgate
check "Version: the CMake project's ($version)" test "$(field Version)" = "$version"
depends=$(field Depends)
echo "Depends: $depends"
# Computed from the binary's libraries, with adduser and openssl for the postinst.
for package in adduser openssl libc6 libstdc++6 libsodium23 libsystemd0 libmosquitto1 libssl3 \
               libtomlplusplus3; do
  check "Depends names $package" grep -q "\b$package\b" <<<"$depends"
done
unit=$(dpkg-deb --fsys-tarfile "$deb" | tar -xO ./lib/systemd/system/tiltgate.service)
check "the service may replace its configuration (the console's apply): ReadWritePaths=/etc/tiltgate" \
  grep -qx 'ReadWritePaths=/etc/tiltgate' <<<"$unit"
check "  and nothing else in /etc" test "$(grep -c '^ReadWritePaths=' <<<"$unit")" = 1
check "the configuration is a conffile" \
  grep -qx /etc/tiltgate/tiltgate.toml <(dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles)
for script in postinst prerm postrm; do
  check "the package has a $script" grep -q "^ *[0-9]* bytes, *[0-9]* lines *\* *$script" \
    <(dpkg-deb -I "$deb")
done

root="$dir/root"
dpkg-deb -x "$deb" "$root"
check "the packaged binary is stripped" bash -c "! readelf -S '$root/usr/bin/tiltgate' | grep -q '\.symtab'"
check "the packaged binary's version" test "$("$root/usr/bin/tiltgate" --version)" = "tiltgate $version"
config="$root/etc/tiltgate/tiltgate.toml"
check "tiltgate check passes on the packaged configuration" \
  "$root/usr/bin/tiltgate" check --config "$config"
check "the packaged configuration serves loopback only" grep -q '^listen = "127.0.0.1"' "$config"
check "the packaged configuration refuses writes" grep -q '^writes = false' "$config"
check "the packaged configuration says so" grep -q 'this machine only until edited' "$config"
check "the packaged configuration names the installed configuration reference" \
  grep -q '/usr/share/doc/tiltgate/docs/configuration\.md' "$config"
doc="$root/usr/share/doc/tiltgate"
for page in "$source_dir"/docs/*.md "$source_dir"/docs/*.png "$source_dir"/README.md; do
  case $page in */README.md) packaged=$doc/README.md ;; *) packaged=$doc/docs/${page##*/} ;; esac
  check "the packaged ${packaged#"$doc"/} is the source's, uncompressed" cmp -s "$page" "$packaged"
done
# Every relative link of the installed README (docs/configuration.md#server, ...) resolves there.
links=$(grep -o '](docs/[^)#]*' "$doc/README.md" | sed 's/^](//' | sort -u)
check "the installed README links to the manual's pages" test -n "$links"
for link in $links; do
  check "the installed README's link to $link resolves" test -f "$doc/$link"
done

# The web console's certificate: the postinst runs the packaged script on /etc/tiltgate with
# group tiltgate; here on a folder of the test's, with a group other than root's when root.
postinst=$(dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./postinst)
check "the postinst gives /etc/tiltgate to the service's group, writable" \
  bash -c "grep -qx '  chgrp tiltgate /etc/tiltgate' <<<\"\$1\" && grep -qx '  chmod 0775 /etc/tiltgate' <<<\"\$1\"" _ "$postinst"
check "the postinst makes the console's certificate" \
  grep -q '^ */usr/libexec/tiltgate/make-console-certificate /etc/tiltgate tiltgate$' <<<"$postinst"
make_certificate=$root/usr/libexec/tiltgate/make-console-certificate
certs=$dir/etc-tiltgate
mkdir -p "$certs"
key_group=$(id -gn)
[ "$(id -u)" = 0 ] && key_group=nogroup
check "the certificate script runs" "$make_certificate" "$certs" "$key_group"
check "it makes a certificate valid for ten years" \
  openssl x509 -in "$certs/console.crt" -noout -checkend $((3649 * 86400))
check "the certificate names localhost" \
  bash -c "openssl x509 -in '$certs/console.crt' -noout -ext subjectAltName | grep -q 'DNS:localhost'"
check "the key is the certificate's" test "$(openssl pkey -in "$certs/console.key" -pubout)" = \
  "$(openssl x509 -in "$certs/console.crt" -noout -pubkey)"
check "the key is mode 0640, group $key_group" test "$(stat -c %a:%G "$certs/console.key")" = "640:$key_group"
check "nothing else is left in the folder" test "$(ls -A "$certs" | tr '\n' ' ')" = "console.crt console.key "
before=$(cat "$certs/console.crt" "$certs/console.key" | sha256sum)
check "a second run keeps the certificate and key there" "$make_certificate" "$certs" "$key_group"
check "  unchanged" test "$(cat "$certs/console.crt" "$certs/console.key" | sha256sum)" = "$before"
rm "$certs/console.crt"
check "a run with only a key there (the plant's own) makes nothing" \
  "$make_certificate" "$certs" "$key_group"
check "  beside it" test ! -e "$certs/console.crt"
check "the packaged configuration names the console's certificate" \
  grep -q '^# tls_cert_file = "/etc/tiltgate/console.crt"' "$config"

# lintian: no error (E:) is allowed; warnings are shown (docs/development.md, "The Debian
# package", lists the ones left and why).
lintian --fail-on error --tag-display-limit 0 "$deb" >"$dir/lintian.log" 2>&1
lintian_status=$?
cat "$dir/lintian.log"
check "lintian reports no errors" test "$lintian_status" = 0

# systemd-analyze verify on the installed tree (--root): the package on top of a copy of this
# machine's units (sysinit.target and the rest it needs) and /bin/kill (ExecReload=), so it
# works in a chroot without a running systemd. It exits 0 on a line it ignores ("Failed to
# parse ..."): any output at all is a finding. The man page (Documentation=) is checked apart,
# as verify would look for it on this machine rather than in the tree.
unit="$root/lib/systemd/system/tiltgate.service"
mkdir -p "$root/usr/lib/systemd/system" "$root/bin"
(cd /usr/lib/systemd/system && tar -cf - --exclude='tiltgate*' .) | tar -xf - -C "$root/usr/lib/systemd/system"
cp /bin/kill "$root/bin/kill"
systemd-analyze verify --root="$root" --man=no /lib/systemd/system/tiltgate.service \
  >"$dir/verify.log" 2>&1
verify_status=$?
cat "$dir/verify.log"
check "systemd-analyze verify passes" test "$verify_status" = 0
check "systemd-analyze verify finds nothing to say" test ! -s "$dir/verify.log"
check "the man page of Documentation= is there" \
  bash -c "MANPATH='$root/usr/share/man' man -w tiltgate"
systemd-analyze security --offline=yes --no-pager "$unit" >"$dir/security.log" 2>&1
exposure=$(sed -n 's/.*Overall exposure level for tiltgate.service: \([0-9.]*\).*/\1/p' "$dir/security.log")
echo "systemd-analyze security: exposure ${exposure:-unknown}"
check "systemd-analyze security: exposure at most 2.5" \
  awk -v level="${exposure:-99}" 'BEGIN { exit !(level <= 2.5) }'

# Bash completion, with bash-completion's _init_completion played by a stub.
complete_line() {  # WORDS...: what completing the last word offers
  PATH="$root/usr/bin:$PATH" bash -c '
    source "$0"
    _init_completion() { words=("${COMP_WORDS[@]}"); cword=$COMP_CWORD; cur=${words[cword]}
                         prev=${words[cword-1]}; }
    COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _tiltgate; echo "${COMPREPLY[*]}"' \
    "$root/usr/share/bash-completion/completions/tiltgate" "$@"
}
check "completion: commands" test "$(complete_line tiltgate ch)" = check
check "completion: a command's options" test "$(complete_line tiltgate run --con)" = --config
check "completion: nested commands" test "$(complete_line tiltgate sim rie)" = rieker
check "completion: the user command's actions" test "$(complete_line tiltgate user pa)" = passwd
check "completion: options after an option's value" \
  test "$(complete_line tiltgate map --config x.toml --for)" = --format

echo "$passes passed, $failures failed"
[ "$failures" = 0 ]
