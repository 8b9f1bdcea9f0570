#!/usr/bin/env bash
# Regenerates Testing/Benchmarks/hot-symbols.txt, the linker's symbol ordering file for the benchmark
# drivers: the functions that short runs of both decks (1 and 2 threads) execute, under valgrind's
# callgrind. With lld, the benchmarks are linked with these functions first and together, so the
# pages of program text that a run touches are few and contiguous (Documentation/performance.md,
# "Program text"). Run it after changes to the step loop; a stale list costs memory, never results.
#   Testing/Benchmarks/make-hot-symbols.sh [BUILD_DIR]     (needs valgrind; 3 minutes on an idle 2-core machine)
set -euo pipefail
cd "$(dirname "$0")/../.."
build="${1:-build}"
command -v valgrind > /dev/null || { echo "make-hot-symbols.sh: valgrind not found (apt-get install valgrind)" >&2; exit 2; }
for exe in PeriodicBoxBenchmark SettleBenchmark; do
  [[ -x "$build/bin/$exe" ]] || { echo "make-hot-symbols.sh: $build/bin/$exe not built" >&2; exit 2; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
profile() {  # EXE OUT ARGS...
  local exe=$1 out=$2
  shift 2
  valgrind --tool=callgrind --dump-instr=yes --callgrind-out-file="$tmp/$out" "$build/bin/$exe" "$@" --quiet > /dev/null 2>&1
}
profile PeriodicBoxBenchmark p1.out --steps 200 --threads 1
profile PeriodicBoxBenchmark p2.out --steps 100 --threads 2
profile SettleBenchmark s1.out --steps 40 --threads 1
profile SettleBenchmark s2.out --steps 30 --threads 2
{
  python3 Testing/Benchmarks/hot-symbols.py "$build/bin/PeriodicBoxBenchmark" "$tmp/p1.out" "$tmp/p2.out"
  python3 Testing/Benchmarks/hot-symbols.py "$build/bin/SettleBenchmark" "$tmp/s1.out" "$tmp/s2.out"
} | awk '!seen[$0]++' > "$tmp/hot-symbols.txt"
# copied next to the list, then renamed: a killed run never leaves a half-written list
cp "$tmp/hot-symbols.txt" Testing/Benchmarks/hot-symbols.txt.tmp
mv Testing/Benchmarks/hot-symbols.txt.tmp Testing/Benchmarks/hot-symbols.txt
echo "make-hot-symbols.sh: $(wc -l < Testing/Benchmarks/hot-symbols.txt) symbols in Testing/Benchmarks/hot-symbols.txt"
