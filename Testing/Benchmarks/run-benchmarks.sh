#!/usr/bin/env bash
# Runs the standard decks (../shared/bench) with 1 and 2 threads, REPEAT times each, and prints the
# median particle-steps per second and the memory figure. Timings need a quiet machine.
#   Testing/Benchmarks/run-benchmarks.sh [BUILD_DIR] [REPEAT]
set -euo pipefail
cd "$(dirname "$0")/../.."
build="${1:-build}"
repeat="${2:-3}"
for exe in PeriodicBoxBenchmark SettleBenchmark; do
  [[ -x "$build/bin/$exe" ]] || { echo "run-benchmarks.sh: $build/bin/$exe not built" >&2; exit 1; }
done
median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
for exe in PeriodicBoxBenchmark SettleBenchmark; do
  for t in 1 2; do
    rates=(); line=""
    for ((k = 0; k < repeat; ++k)); do
      out=$("$build/bin/$exe" --threads "$t" --quiet 2>/dev/null)
      line=$(grep "particle_steps_per_s" <<<"$out")
      rates+=("$(sed 's/.*particle_steps_per_s=\([^ ]*\).*/\1/' <<<"$line")")
      endline=$(grep " end " <<<"$out")
    done
    med=$(printf '%s\n' "${rates[@]}" | median)
    echo "$exe threads=$t median_particle_steps_per_s=$med runs=[${rates[*]}] | $endline | ${line##* }"
  done
done
