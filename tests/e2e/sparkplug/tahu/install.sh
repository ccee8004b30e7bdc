#!/usr/bin/env bash
# Installs Eclipse Tahu's sparkplug-payload, as package-lock.json beside this script pins it,
# from the npm registry into DIR/node_modules (npm ci), for the Sparkplug e2e tests' second
# decoder (decode.js, spb_e2e/tahu.py). Done again only when the lock file changed. No registry
# (or no npm) is a failure: the tests that need the decoder must not pass without it.
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
# No install scripts: the decoder needs none, and they are code the test does not need to run.
npm ci --ignore-scripts --no-audit --no-fund
node -e 'require("sparkplug-payload")' || { echo "tahu: sparkplug-payload does not load" >&2; exit 1; }
echo "tahu: sparkplug-payload installed in $dir"
