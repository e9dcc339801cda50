#!/usr/bin/env bash
# Validates glTF files (.glb or .gltf) with the Khronos glTF-Validator (npm package gltf-validator, the official
# validator compiled to JavaScript) and prints its errors and warnings.
#
#   scripts/validate-gltf.sh [--strict] FILE...    exit 0 when no file has errors (--strict: nor warnings)
#
# The validator is installed on first use with npm into $GLTF_VALIDATOR_DIR (default: build-gltf-validator/ at the
# repository root, which .gitignore's /build*/ keeps out of git). The install is one 400 kB package with no
# dependencies (about 1 s). Set GLTF_VALIDATOR_NO_INSTALL=1 to fail instead of installing (offline CI).
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
dir=${GLTF_VALIDATOR_DIR:-$repo/build-gltf-validator}
version=2.0.0-dev.3.10  # pinned: reports are compared across runs

strict=0
if [[ ${1:-} == --strict ]]; then
  strict=1
  shift
fi
if [[ $# -eq 0 ]]; then
  echo "usage: $0 [--strict] FILE.glb..." >&2
  exit 2
fi
command -v node >/dev/null || { echo "validate-gltf: node is not installed" >&2; exit 2; }

if [[ ! -f $dir/node_modules/gltf-validator/index.js ]]; then
  if [[ ${GLTF_VALIDATOR_NO_INSTALL:-0} == 1 ]]; then
    echo "validate-gltf: gltf-validator missing in $dir and GLTF_VALIDATOR_NO_INSTALL=1" >&2
    exit 2
  fi
  echo "validate-gltf: installing gltf-validator@$version into $dir" >&2
  mkdir -p "$dir"
  npm install --prefix "$dir" --no-audit --no-fund --silent "gltf-validator@$version" >&2
fi

NODE_PATH=$dir/node_modules STRICT=$strict node - "$@" <<'JS'
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');
const severity = ['error', 'warning', 'info', 'hint'];
(async () => {
  let failed = 0;
  for (const file of process.argv.slice(2)) {
    let report;
    try {
      report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
        uri: path.basename(file),
        maxIssues: 100,
        // .glb files are self-contained; a .gltf may reference files next to it.
        externalResourceFunction: (uri) => new Promise((resolve, reject) =>
          fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)), (e, d) => (e ? reject(e.toString()) : resolve(d)))),
      });
    } catch (e) {
      console.log(`${file}: validator failed: ${e}`);
      failed++;
      continue;
    }
    const i = report.issues;
    console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints` +
                ` (glTF-Validator ${report.validatorVersion})`);
    for (const m of i.messages)
      if (m.severity <= 1 || process.env.VERBOSE)
        console.log(`  ${severity[m.severity]} ${m.code} ${m.pointer || ''}: ${m.message}`);
    if (i.numErrors > 0 || (process.env.STRICT === '1' && i.numWarnings > 0)) failed++;
  }
  process.exit(failed ? 1 : 0);
})();
JS
