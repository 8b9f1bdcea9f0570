#!/usr/bin/env bash
# Builds and runs the fast test suite (everything except the labels "validation" and "benchmark").
#   scripts/test.sh              the normal suite (Release build in build/)
#   scripts/test.sh --sanitize   the sanitizer suite: unit + selftest (not "heavy") under ASan/UBSan (build-sanitize/)
#   scripts/test.sh --all        both (what .ci/run does)
#   scripts/test.sh --quick      the normal suite (kept for compatibility: same as no flag)
# Exits non-zero if any test fails.
set -euo pipefail
cd "$(dirname "$0")/.."

sanitize_only=0
quick=0
all=0
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize_only=1 ;;
    --quick) quick=1 ;;
    --all) all=1 ;;
    -h|--help) echo "usage: $0 [--sanitize] [--all] [--quick]"; exit 0 ;;
    *) echo "test.sh: unknown argument '$arg' (usage: $0 [--sanitize] [--all] [--quick])" >&2; exit 2 ;;
  esac
done

# ctest runs two tests at once on two cores, and each kernel test opens two OpenMP threads. With
# libgomp's default (active) waiting, a thread spins at every barrier while its partner is
# descheduled by the other test: CgInSitu took 0.7 s alone and 40 s (Release) to over 300 s
# (sanitizers, CI time-out, 2026-12-06) side by side. Passive waiting sleeps instead; results are
# unchanged (the schedules are static), only the waiting differs. Unit and self-tests set it too.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-PASSIVE}"

run_normal() {
  scripts/build.sh
  echo "== test.sh: normal suite (build/)" >&2
  ctest --test-dir build --output-on-failure -j2 -LE 'validation|benchmark'
}

run_sanitize() {
  scripts/build.sh --sanitize
  # the quick subset: unit tests and self-tests except those labelled "heavy" (5-7 min each
  # under the sanitizers) and "release_only" (physics checks on a bed that another floating-point
  # build pours differently); the normal suite runs them
  echo "== test.sh: sanitizer suite (build-sanitize/, labels unit|selftest, not heavy|release_only)" >&2
  ASAN_OPTIONS=detect_leaks=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-sanitize --output-on-failure -j2 -L 'unit|selftest' -LE 'heavy|release_only'
}

if [[ $sanitize_only -eq 1 ]]; then
  run_sanitize
  exit 0
fi

run_normal
if [[ $all -eq 1 && $quick -eq 0 && "${PDPM_SKIP_SANITIZE:-0}" != "1" ]]; then
  run_sanitize
fi
echo "== test.sh: all tests passed" >&2
