#!/usr/bin/env bash
# Times one FT4-preset protocol-1 run of OedometerRelaxation (issue target: under 15 minutes on
# 2 cores) and prints wall seconds and particle-steps per second of the pour and of the protocol.
# Needs a quiet machine (Documentation/performance.md).
#   Testing/Benchmarks/oedometer-ft4.sh [BUILD_DIR] [THREADS] [OUT_DIR] [extra driver flags...]
bench_program=OedometerRelaxation
source "$(dirname "$0")/driver-bench-args.sh"
start=$(date +%s.%N)
"$exe" --preset ft4 --threads "$threads" --output "$out" --name ft4_p1 "$@" >"$out/ft4_p1.stdout" 2>"$out/ft4_p1.stderr"
end=$(date +%s.%N)
# progress lines end with "N steps in H:MM:SS (R steps/s)": the first is the pour, the last the protocol
tr '\r' '\n' <"$out/ft4_p1.stderr" | grep "steps in" >"$out/ft4_p1.phases" || true
line=$(grep "particles poured" "$out/ft4_p1.stdout")
n_bed=$(sed 's/^OedometerRelaxation: \([0-9]*\) particles.*/\1/' <<<"$line")
n_pour=$(sed 's/.* with \([0-9.e+]*\) particles poured.*/\1/' <<<"$line")
rate() { sed 's/.*(\([0-9.e+]*\) steps\/s).*/\1/' <<<"$1"; }
pour=$(head -1 "$out/ft4_p1.phases"); prot=$(tail -1 "$out/ft4_p1.phases")
python3 - "$start" "$end" "$n_pour" "$n_bed" "$(rate "$pour")" "$(rate "$prot")" "$threads" <<'PY'
import sys
s, e, npour, nbed, rpour, rprot, th = sys.argv[1:]
print(f"ft4_protocol1 threads={th} wall_s={float(e) - float(s):.1f} poured={float(npour):.0f} bed={nbed} "
      f"pour_particle_steps_per_s={float(npour) * float(rpour):.3g} protocol_particle_steps_per_s={float(nbed) * float(rprot):.3g}")
PY
grep -E "^  step " "$out/ft4_p1.stdout" || true
echo "output in $out"
