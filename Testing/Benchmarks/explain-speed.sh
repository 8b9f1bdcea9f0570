#!/usr/bin/env bash
# Times pdpm-explain's surrogate stages (calibration, noise model, screening, selection, held-out
# errors, windows, report; --dem off) on generated recordings of SAMPLES samples (issue target: one
# recording of about 1e4 samples in at most 60 s on 2 cores) and prints each case's wall seconds and
# the median / largest (null, every mechanism the generator makes -- rolling_resistance needs a lateral
# stress channel, which it does not make -- a two-mechanism case and the out-of-library sine).
# Timings need a quiet machine (Documentation/performance.md).
#   Testing/Benchmarks/explain-speed.sh [BUILD_DIR] [THREADS] [OUT_DIR] [SAMPLES] [SEEDS]
#   SAMPLES defaults to 10000, SEEDS (how many seeds per kind) to 3; THREADS is OMP_NUM_THREADS.
bench_program=pdpm-explain
source "$(dirname "$0")/driver-bench-args.sh"
samples="${1:-10000}"
seeds="${2:-3}"
data="$build/bin/pdpm-explain-data"
[[ "$samples" =~ ^[0-9]+$ && "$seeds" =~ ^[0-9]+$ && "$seeds" -ge 1 ]] ||
  { echo "explain-speed.sh: SAMPLES and SEEDS must be whole numbers, SEEDS at least 1" >&2; exit 2; }
[[ -x "$data" ]] || { echo "explain-speed.sh: $data not built" >&2; exit 1; }
kinds=(null contact_relaxation plasticity cohesion wall_friction rate_dependence stiffness_nonlinearity
       two:contact_relaxation+plasticity ool:sine)
times=()
printf '%-36s %5s %8s  %s\n' case seed wall_s verdict
for kind in "${kinds[@]}"; do
  for ((seed = 1; seed <= seeds; ++seed)); do
    name="${kind//[:+]/_}_$seed"
    "$data" generate --kind "$kind" --snr 3 --rho 0.5 --seed "$seed" --samples "$samples" \
      --output "$out/$name" --truth "$out/$name.truth.json" >/dev/null
    start=$(date +%s.%N)
    OMP_NUM_THREADS="$threads" "$exe" --recording "$out/$name/recording.csv" --protocol "$out/$name/protocol.json" \
      --output "$out/$name.explained" --dem off --no_figures 1 >"$out/$name.log" 2>&1 ||
      { echo "explain-speed.sh: pdpm-explain failed on $name (see $out/$name.log)" >&2; exit 1; }
    end=$(date +%s.%N)
    wall=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" "$start" "$end")
    times+=("$wall")
    verdict=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['verdict'])" "$out/$name.explained/report.json")
    printf '%-36s %5d %8s  %s\n' "$kind" "$seed" "$wall" "$verdict"
  done
done
printf '%s\n' "${times[@]}" | python3 -c "
import sys, statistics
t = [float(x) for x in sys.stdin]
print(f'explain_surrogate samples={sys.argv[1]} threads={sys.argv[2]} cases={len(t)} median_wall_s={statistics.median(t):.2f} '
      f'max_wall_s={max(t):.2f} above_60_s={sum(x > 60 for x in t)}')" "$samples" "$threads"
echo "output in $out"
