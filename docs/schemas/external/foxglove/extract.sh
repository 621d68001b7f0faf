#!/bin/sh
# Reproduce the Foxglove schemas of this folder from their npm package
# (SOURCES.md): fetch @foxglove/schemas 2.1.0 with npm, check the tarball's
# sha256, and write each schema the package exports
# (require("@foxglove/schemas/jsonschema")) that this folder holds, as
# JSON.stringify(schema, null, 2) plus a newline. Needs npm and node.
#
#   sh docs/schemas/external/foxglove/extract.sh OUT_DIR
#   diff -r OUT_DIR docs/schemas/external/foxglove   # only SOURCES.md and extract.sh differ
set -eu
VERSION=2.1.0
SHA256=c6d2746e10bbb451a680307b6e5ec3b186de3263df2a41869a7757b3042fcbf0
OUT=$(mkdir -p "${1:?usage: extract.sh OUT_DIR}" && cd "$1" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
npm pack --silent "@foxglove/schemas@$VERSION" > /dev/null
echo "$SHA256  foxglove-schemas-$VERSION.tgz" | sha256sum -c - > /dev/null
tar xzf "foxglove-schemas-$VERSION.tgz"
OUT="$OUT" node -e '
const s = require("./package/jsonschema.js"), fs = require("fs");
for (const k of ["FrameTransforms", "SceneUpdate", "PointCloud"])
  fs.writeFileSync(process.env.OUT + "/" + k + ".json", JSON.stringify(s[k], null, 2) + "\n");'
ls "$OUT"
