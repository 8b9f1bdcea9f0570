#!/usr/bin/env bash
# Builds PowderDPM and runs the demo simulation.
# Usage: scripts/demo.sh [OUTPUT_DIR]   (default: demo-output)
set -euo pipefail
cd "$(dirname "$0")/.."

out="${1:-demo-output}"
scripts/build.sh
if [[ ! -x build/bin/Demo ]]; then
  echo "demo.sh: build/bin/Demo was not built" >&2
  exit 1
fi
build/bin/Demo --output "$out"
echo
echo "demo.sh: outputs are in $(cd "$out" && pwd):"
ls -1 "$out" | sed "s/^/  /" | head -n 40 || true
