#!/bin/sh
# Builds editor/dist/vendor from the pinned npm packages (package-lock.json).
# The page itself (dist/index.html, app.js, viewer.js, util.js, style.css) is
# hand-written and lives in dist/ directly; `fairsurf serve` embeds dist/.
set -eu
cd "$(dirname "$0")"

npm ci --no-audit --no-fund

src=node_modules/three
vendor=dist/vendor
rm -rf "$vendor"
mkdir -p "$vendor/addons/controls" "$vendor/addons/lines"

# three r150+ is ES modules only; three.module.js imports ./three.core.js.
cp "$src/build/three.module.js" "$src/build/three.core.js" "$vendor/"
# The add-ons the page imports (keep in sync with dist/viewer.js). They
# import 'three' (resolved by the importmap in index.html) and each other
# by relative paths, so the directory layout is kept.
cp "$src/examples/jsm/controls/OrbitControls.js" "$vendor/addons/controls/"
for f in LineSegments2.js LineSegmentsGeometry.js LineMaterial.js; do
  cp "$src/examples/jsm/lines/$f" "$vendor/addons/lines/"
done
cp "$src/LICENSE" "$vendor/three.LICENSE"

echo "editor/dist/vendor: three $(node -p "require('./$src/package.json').version")"
du -sh dist
