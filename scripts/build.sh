#!/usr/bin/env bash
# Builds PowderDPM: build/ (Release), or build-sanitize/ (ASan+UBSan, RelWithDebInfo) with --sanitize.
# Usage: scripts/build.sh [--sanitize]
set -euo pipefail
cd "$(dirname "$0")/.."

sanitize=0
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize=1 ;;
    -h|--help) echo "usage: $0 [--sanitize]"; exit 0 ;;
    *) echo "build.sh: unknown argument '$arg' (usage: $0 [--sanitize])" >&2; exit 2 ;;
  esac
done

scripts/install-deps.sh

jobs=$(nproc 2>/dev/null || echo 2)
if [[ $sanitize -eq 1 ]]; then
  cmake -S . -B build-sanitize -DPDPM_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
  cmake --build build-sanitize -j"$jobs"
else
  cmake -S . -B build
  cmake --build build -j"$jobs"
fi
