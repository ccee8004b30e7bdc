#!/usr/bin/env bash
# Installs Eclipse Tahu's sparkplug-payload, as package-lock.json beside this script pins it,
# from the npm registry into DIR/node_modules (npm ci), for the Sparkplug e2e tests' second
# decoder (decode.js, spb_e2e/tahu.py). Done again only when the lock file changed.
# No npm, or an install that fails otherwise, is a failure. A registry this machine cannot reach
# (no route or name, or a TLS proxy whose certificate authority it does not trust, as in a bare
# chroot behind one) is an environment limitation: the fixture is skipped (exit 77), the reason
# is written to DIR/unreachable, and the Sparkplug tests run their protoc checks, saying loudly
# that Tahu's comparison could not run here.
# Usage: install.sh DIR
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
dir="$1"
mkdir -p "$dir"
if [ -f "$dir/node_modules/sparkplug-payload/package.json" ] &&
   cmp -s "$here/package-lock.json" "$dir/package-lock.json"; then
  echo "tahu: sparkplug-payload already installed in $dir"
  exit 0
fi
command -v npm >/dev/null || { echo "tahu: no npm (scripts/setup installs it)" >&2; exit 1; }
cp "$here/package.json" "$here/package-lock.json" "$dir/"
cd "$dir"
rm -f unreachable
# No install scripts: the decoder needs none, and they are code the test does not need to run.
if ! npm ci --ignore-scripts --no-audit --no-fund >npm.log 2>&1; then
  cat npm.log >&2
  # npm's error codes for a registry that cannot be reached or whose certificate is not trusted.
  reason=$(grep -o -m1 -E 'SELF_SIGNED_CERT_IN_CHAIN|UNABLE_TO_GET_ISSUER_CERT(_LOCALLY)?|UNABLE_TO_VERIFY_LEAF_SIGNATURE|DEPTH_ZERO_SELF_SIGNED_CERT|CERT_HAS_EXPIRED|ENOTFOUND|EAI_AGAIN|ECONNREFUSED|ECONNRESET|ETIMEDOUT|ENETUNREACH|EHOSTUNREACH' npm.log || true)
  if [ -n "$reason" ]; then
    echo "the npm registry cannot be reached from this machine ($reason)" >unreachable
    echo "tahu: SKIPPED: the npm registry cannot be reached from this machine ($reason)" >&2
    exit 77
  fi
  echo "tahu: npm ci failed" >&2
  exit 1
fi
node -e 'require("sparkplug-payload")' || { echo "tahu: sparkplug-payload does not load" >&2; exit 1; }
echo "tahu: sparkplug-payload installed in $dir"
