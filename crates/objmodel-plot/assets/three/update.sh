#!/usr/bin/env bash
# Rebuild three.bundle.min.js from the versions pinned in package.json / package-lock.json
# (from the npm registry). To move to another three.js: change "three" in package.json, run
# `npm install` here once (it rewrites package-lock.json), then this script, then the browser
# test: `OBJMODEL_REQUIRE_CHROMIUM=1 cargo test -p objmodel-plot --test view`.
set -euo pipefail
cd "$(dirname "$0")"
npm ci --no-audit --no-fund
npx esbuild entry.js --bundle --format=iife --global-name=THREE --minify \
  --legal-comments=eof --outfile=three.bundle.min.js
cp node_modules/three/LICENSE LICENSE
if grep -qi '</script' three.bundle.min.js; then
  echo "three.bundle.min.js contains '</script': it cannot be inlined into HTML" >&2
  exit 1
fi
echo "three $(node -p 'require("./node_modules/three/package.json").version'): $(wc -c < three.bundle.min.js) bytes"
