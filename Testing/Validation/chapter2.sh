#!/usr/bin/env bash
# Thesis chapter 2 (frictionless, N = 9261, preset thesis-ch2): ISO cycle, UNI cycle from v0, D2/D3 at
# several v_i from the ISO unloading branch, UNI cycles from v_i = 0.671/0.695/0.728 on that branch
# (Fig. 2.12/2.14); Table 2.2-style fits and the comparison of Sec. 2.5-2.7.
# Usage: chapter2.sh BIN_DIR SOURCE_DIR [THREADS]      (days of CPU time at full scale)
# Environment: D2_RATE (strain-rate amplitude of the z axis, 1/s; default 5.27, the thesis' slow rate),
#   D2_EPS (deviatoric strain to reach, default 0.3), MODES ("D2 D3"), VS (v_i list, three decimals as
#   in the restart names), UNI_VS (start fractions of the Fig. 2.12 UNI runs, default 0.671 0.695 0.728),
#   SKIP_RUNS=1 (analyse the files already in ch2/).
# Checks (exit 1 if one fails): C* fits (C0 = 6) within v_c +-0.004, alpha +-0.05, C1 +-10 % of
# Table 2.2 for ISO and UNI unloading; v_c(ISO) > v_c(UNI) > v_c(D2); p0 within 10 %.
# v_c(D2): Eq. 2.11 through the steady-state C* of the D2 runs (pdpm-fit steady, eps_dev >= 0.08),
# with C1 and alpha free when there are at least four run files, else fixed at the ISO fit's values
# (a run that never reached the steady state is skipped by pdpm-fit with a warning).
set -euo pipefail
bin="$1"; src="$2"; threads="${3:-2}"
ref="$src/../shared/data/thesis/table_2_2_frictionless_fits.csv"
rate="${D2_RATE:-5.27}"; epsmax="${D2_EPS:-0.3}"; modes="${MODES:-D2 D3}"
vs=$(for v in ${VS:-0.68 0.70 0.72 0.75 0.78}; do printf '%.3f ' "$v"; done)   # restart names carry three decimals
uvs=$(for v in ${UNI_VS:-0.671 0.695 0.728}; do printf '%.3f ' "$v"; done)
ref23="$src/../shared/data/thesis/table_2_3_deviatoric_evolution.csv"
epsmin=$(python3 -c "print(min(0.08, 0.5 * $epsmax))")                       # steady state: second half at least
common=(--preset thesis-ch2 --threads "$threads" --quiet --vtk 0)
if [[ "${SKIP_RUNS:-0}" != 1 ]]; then
  "$bin/IsotropicCompression" "${common[@]}" --output ch2 --name ISO --save_fractions "$(echo $vs $uvs | tr ' ' ,)"
  "$bin/UniaxialCyclic" "${common[@]}" --output ch2 --name UNI
  for v in $uvs; do
    "$bin/UniaxialCyclic" "${common[@]}" --output ch2 --name "UNI_$v" --start "ch2/ISO.unload_$v.restart"
  done
  for v in $vs; do
    for m in $modes; do
      "$bin/DeviatoricD2" "${common[@]}" --output ch2 --name "${m}_$v" --mode "$m" --rate "$rate" --eps_dev_max "$epsmax" \
        --start "ch2/ISO.unload_$v.restart"
    done
  done
fi
"$bin/pdpm-fit" table ch2/ISO.macro.csv ch2/UNI.macro.csv | tee ch2/table_2_2_measured.txt
shopt -s nullglob
d2=(ch2/D2_*.macro.csv)
(( ${#d2[@]} > 0 )) || { echo "chapter2.sh: no ch2/D2_*.macro.csv to analyse"; exit 1; }
shape=()
if (( ${#d2[@]} < 4 )); then
  read -r c1 al < <(awk 'NR == 2 { print $2, $3 }' ch2/table_2_2_measured.txt)
  shape=(--c1 "$c1" --alpha "$al")
fi
"$bin/pdpm-fit" steady "${d2[@]}" --eps_min "$epsmin" "${shape[@]}" | tee ch2/d2_steady.txt
"$bin/pdpm-fit" model --uni ch2/UNI.macro.csv "${d2[@]}" | tee ch2/table_2_3_measured.txt || true
# Sec. 2.7.3: predict the UNI runs started on the ISO unloading branch from the D2/D3 calibration (and
# from the thesis' Table 2.3 when present); Fig. 2.12 (s_dev) and Fig. 2.14 (F_dev) as PNGs
t23=(); [[ -f "$ref23" ]] && t23=(--table "$ref23")
cal=(); (( ${#d2[@]} >= 3 )) && cal=("${d2[@]}")   # the calibration needs three runs at least
preds=()
: > ch2/uni_predictions.txt
for v in $uvs; do
  [[ -f "ch2/UNI_$v.macro.csv" ]] || continue
  rm -f "ch2/pred_UNI_$v.csv"
  (( ${#cal[@]} + ${#t23[@]} > 0 )) || continue
  "$bin/pdpm-fit" model --uni "ch2/UNI_$v.macro.csv" "${cal[@]}" "${t23[@]}" --out "ch2/pred_UNI_$v.csv" \
    | grep '^prediction of' | tee -a ch2/uni_predictions.txt || true
  [[ -f "ch2/pred_UNI_$v.csv" ]] && preds+=("ch2/pred_UNI_$v.csv")
done
if (( ${#preds[@]} > 0 )) && command -v gnuplot > /dev/null; then
  for q in s_dev F_dev; do
    fig=$([[ $q == s_dev ]] && echo fig_2_12 || echo fig_2_14)
    {
      echo "set terminal pngcairo size 900,600 noenhanced; set output 'ch2/$fig.png'; set datafile separator ','"
      echo "set key autotitle columnhead; set grid; set xlabel 'deviatoric strain eps_dev'; set ylabel '$q'"
      printf "plot "
      k=0
      for f in "${preds[@]}"; do
        vi=$(basename "$f" .csv | sed 's/pred_UNI_//')
        (( k > 0 )) && printf ", "
        printf "'%s' u 'eps_dev':'%s' w p pt 7 ps 0.6 lc %d t 'DEM v_i = %s'" "$f" "$q" "$((k + 1))" "$vi"
        # model lines in the run's colour, titled once: solid = D2/D3 calibration, dashed = Table 2.3
        t1=$([[ $k == 0 ]] && echo "t 'Eq. 2.17/2.18 from D2/D3 runs (solid)'" || echo notitle)
        t2=$([[ $k == 0 ]] && echo "t 'Eq. 2.17/2.18 from thesis Table 2.3 (dashed)'" || echo notitle)
        (( ${#cal[@]} > 0 )) && printf ", '%s' u 'eps_dev':'%s_pred_runs' w l lw 2 lc %d %s" "$f" "$q" "$((k + 1))" "$t1"
        (( ${#t23[@]} > 0 )) && printf ", '%s' u 'eps_dev':'%s_pred_table' w l dt 2 lc %d %s" "$f" "$q" "$((k + 1))" "$t2"
        k=$((k + 1))
      done
      echo
    } > "ch2/$fig.gp"
    gnuplot "ch2/$fig.gp" || echo "chapter2.sh: gnuplot failed for $fig"
  done
fi
if [[ ! -f "$ref" ]]; then echo "SKIP: chapter2.sh: reference $ref absent: comparison skipped"; exit 77; fi
python3 - "$ref" ch2/table_2_2_measured.txt ch2/d2_steady.txt <<'PY'
import sys, csv
ref = {r['mode']: r for r in csv.DictReader(l for l in open(sys.argv[1]) if not l.startswith('#'))}
rows = [l.split() for l in open(sys.argv[2]).read().splitlines()[1:]]
meas = {('ISO' if r[0].startswith('ISO') else 'UNI'): dict(C1=float(r[1]), alpha=float(r[2]), vc=float(r[3]), p0=float(r[6])) for r in rows}
ok = True
print(f"{'mode':5} {'quantity':8} {'thesis':>9} {'measured':>9} {'pass':>5}")
for m in ('ISO', 'UNI'):
    t, x = ref[m], meas[m]
    for q, tv, tol in (('v_c', float(t['v_c_Cstar']), ('abs', 0.004)), ('alpha', float(t['alpha']), ('abs', 0.05)),
                       ('C1', float(t['C1']), ('rel', 0.10)), ('p0', float(t['p0']), ('rel', 0.10))):
        mv = x['vc' if q == 'v_c' else q]
        good = abs(mv - tv) <= (tol[1] if tol[0] == 'abs' else tol[1] * abs(tv))
        ok &= good
        print(f"{m:5} {q:8} {tv:9.4f} {mv:9.4f} {str(good):>5}")
good = meas['ISO']['vc'] > meas['UNI']['vc']
print("ordering v_c(ISO) > v_c(UNI):", good); ok &= good
# the same statement at equal v: C*(ISO fit) < C*(UNI fit) < C*(D2 steady state) (thesis Fig. 2.6 inset)
fits = {('ISO' if r[0].startswith('ISO') else 'UNI'): [float(x) for x in r[1:4]] for r in rows}
cstar = lambda f, v: 6 + f[0] * max(v / f[2] - 1, 0) ** f[1]
for l in open(sys.argv[3]):
    w = l.split()
    if len(w) == 9 and w[0].endswith('.csv'):
        v, c = float(w[2]), float(w[3])
        print(f"v = {v:.3f}: C* ISO {cstar(fits['ISO'], v):.3f}, UNI {cstar(fits['UNI'], v):.3f}, D2 steady {c:.3f}")
vd = [float(l.split()[2]) for l in open(sys.argv[3]) if l.strip().startswith('v_c')]
if vd:
    good = meas['UNI']['vc'] > vd[0]
    print(f"v_c(D2) {vd[0]:.4f} (thesis {float(ref['D2']['v_c_Cstar']):.4f}); ordering v_c(UNI) > v_c(D2):", good); ok &= good
else:
    print("v_c(D2): no fit (see ch2/d2_steady.txt)"); ok = False
sys.exit(0 if ok else 1)
PY
