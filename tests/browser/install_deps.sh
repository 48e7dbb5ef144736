#!/usr/bin/env bash
# Installs the browser tests' Node packages (exactly package-lock.json, with npm ci) into DIR
# (default: build/browser), once, and again only when the lock file changes. The browser itself
# is Debian's chromium (tools/scripts/setup.sh installs it); playwright-core downloads none.
set -euo pipefail
src="$(cd "$(dirname "$0")" && pwd)"
dest="${1:-$src/../../build/browser}"
mkdir -p "$dest"
if [ -d "$dest/node_modules/playwright-core" ] && cmp -s "$src/package-lock.json" "$dest/package-lock.json"; then
  exit 0
fi
cp "$src/package.json" "$src/package-lock.json" "$dest/"
cd "$dest"
npm ci --no-audit --no-fund --loglevel=error
