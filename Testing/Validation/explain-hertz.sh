#!/bin/bash
# stiffness_nonlinearity end to end on records made by the OedometerRelaxation driver itself (the
# table of Documentation/tools-explain.md, "Stiffness nonlinearity"): load to 20 kPa, unload to
# 1 kPa, reload to 20 kPa, the non-cohesive frictional material, elastic contacts, no adhesion or
# relaxation, a laterally periodic bed of about 940 particles (10 x 10 mean diameters). Records with
# Hertz contacts (E* = 5e7 Pa, fill seeds 777, 778, 780; E* = 1.5e7 Pa, seed 779) and linear twins
# (seeds 777, 778). pdpm-explain confirms stiffness_nonlinearity with the DEM where it accepts it
# (`--dem fast --dem_mechanism stiffness_nonlinearity`; the confirmation's beds use the driver's
# default seed, never a record's). One thread per run, two records side by side: about 14 min for the
# one-level cases, 13 min for the two-level ones; all 12 with the soft ones 38 min on a shared VM
# (session 43) (HERTZ_CASES=one|two|all).
# Since session 43 also records of linear contacts as soft as those Hertzian ones at the top stress
# (k x 0.215, seeds 777 and 778, one level: "soft"), whose unloading is as curved.
# Prints one line per record; fails if a run fails, if a Hertz record's DEM confirmation is not done
# or does not lower the held-out reload error or has no control run (linear contacts as soft as the
# chosen Hertzian ones) or does not favour Hertz's law over that control (gated since session 43;
# reported before), if a soft linear record's confirmation favours Hertz's law, or if a linear twin
# that the surrogate answers with stiffness_nonlinearity is not "contradicted" by the DEM.
# HERTZ_NOISE_PA=SD (since session 44) adds AR(1) noise (lag-1 coefficient 0.5, marginal sd SD Pa,
# seeded by the record's seed) to the axial, bottom and lateral stress of every record, quantised to
# 1 Pa, before pdpm-explain reads it; the gates then ask less: a Hertz record's confirmation may be
# "inconclusive" (its curvature within two noise spreads of the linear bed's) but never "contradicted",
# and when done it must not favour linear contacts; a soft record's must not favour Hertz's law.
# Since session 43 the held-out reloads are followed from their own first sample (the confirmation's
# bed is not the record's; on the u scale the strain another bed's unload recovers offsets the whole
# reload, which made this gate fail on seeds 777 and 780 in session 42): the error falls by 60-94 % on
# all 7 Hertz records (Documentation/tools-explain.md, "The reload judged from its start").
source "$(dirname "$0")/explain-common.sh"
# one level: load 20 kPa - unload 1 kPa - reload 20 kPa; two levels (cases marked "2"): a first cycle
# to 5 kPa (unload to 250 Pa) before it, so that the control run is judged by how the unloading
# stiffness grows with the stress (DemConfirmation.h)
cat > "$OUT/protocol.json" <<'JSON'
{"format": "pdpm-oedometer-protocol", "version": 1, "source": "experiment",
 "device": {"name": "oedometer", "diameter_m": 0.015, "height_m": 0.015, "wall_friction": 0}, "material": {"name": "frictional"},
 "steps": [{"type": "ramp", "velocity_m_s": 1e-5, "target_stress_Pa": 20000},
           {"type": "unload", "velocity_m_s": 1e-5, "target_stress_Pa": 1000},
           {"type": "ramp", "velocity_m_s": 1e-5, "target_stress_Pa": 20000}]}
JSON
cat > "$OUT/protocol2.json" <<'JSON'
{"format": "pdpm-oedometer-protocol", "version": 1, "source": "experiment",
 "device": {"name": "oedometer", "diameter_m": 0.015, "height_m": 0.015, "wall_friction": 0}, "material": {"name": "frictional"},
 "steps": [{"type": "ramp", "velocity_m_s": 1e-5, "target_stress_Pa": 5000},
           {"type": "unload", "velocity_m_s": 1e-5, "target_stress_Pa": 250},
           {"type": "ramp", "velocity_m_s": 1e-5, "target_stress_Pa": 20000},
           {"type": "unload", "velocity_m_s": 1e-5, "target_stress_Pa": 1000},
           {"type": "ramp", "velocity_m_s": 1e-5, "target_stress_Pa": 20000}]}
JSON
one() {  # seed modulus (0: linear contacts; soft: linear contacts k x 0.215) [2: two levels]
  local name="s$1_E$2" hertz=() proto="$OUT/protocol.json"
  if [ "$2" = soft ]; then hertz=(--normal_stiffness_scale 0.215)
  elif [ "$2" != 0 ]; then hertz=(--hertz_modulus "$2"); fi
  [ "${3:-}" = 2 ] && name="${name}_2" proto="$OUT/protocol2.json"
  "$BIN/OedometerRelaxation" --protocol_file "$proto" --material frictional --width 10 --fill_height 10 --seed "$1" \
    --relax_C 0 --kc_over_k 0 --k_over_k1 1 ${hertz[@]+"${hertz[@]}"} --output "$OUT/records" --name "$name" --quiet --vtk 0 --ene 0 --threads 1 \
    > "$OUT/records-$name.log" 2>&1
  if [ -n "${HERTZ_NOISE_PA:-}" ]; then
    python3 - "$OUT/records/$name.recording.csv" "$HERTZ_NOISE_PA" "$1" <<'PY'
import math, os, random, sys
path, sd, seed = sys.argv[1], float(sys.argv[2]), int(sys.argv[3])
rng, rho = random.Random(seed), 0.5
lines = open(path).read().splitlines()
head = [l for l in lines if l.startswith('#')]
body = [l for l in lines if not l.startswith('#')]
cols = body[0].split(',')
idx = [cols.index(c) for c in ('axial_stress_Pa', 'bottom_stress_Pa', 'lateral_stress_Pa') if c in cols]
ar = {i: rng.gauss(0, sd) for i in idx}
out = head + [f'# noise added: AR(1) rho {rho}, sd {sd} Pa, quantised to 1 Pa, seed {seed}', body[0]]
for row in body[1:]:
    f = row.split(',')
    for i in idx:
        ar[i] = rho * ar[i] + math.sqrt(1 - rho * rho) * rng.gauss(0, sd)
        f[i] = str(round(float(f[i]) + ar[i]))
    out.append(','.join(f))
open(path + '.tmp', 'w').write('\n'.join(out) + '\n')
os.replace(path + '.tmp', path)
PY
  fi
  OMP_NUM_THREADS=1 "$BIN/pdpm-explain" --recording "$OUT/records/$name.recording.csv" --protocol "$OUT/records/$name.protocol.json" \
    --output "$OUT/$name" --dem fast --dem_threads 1 --dem_mechanism stiffness_nonlinearity --no_figures 1 > "$OUT/$name.log" 2>&1
}
# HERTZ_CASES: "one", "two" or "all" (default)
cases=${HERTZ_CASES:-all}
case "$cases" in one|two|all) ;; *) echo "HERTZ_CASES: expected one, two or all, got '$cases'" >&2; exit 2;; esac
pairs=()
[ "$cases" != two ] && pairs+=("777 5e7" "777 0" "778 5e7" "778 0" "779 1.5e7" "780 5e7" "777 soft" "778 soft")
[ "$cases" != one ] && pairs+=("777 5e7 2" "778 5e7 2" "780 5e7 2" "778 0 2")
(( ${#pairs[@]} % 2 == 0 )) || { echo "explain-hertz.sh: the cases run two at a time; give an even number" >&2; exit 2; }
failed=0
names=()
for ((i = 0; i < ${#pairs[@]}; i += 2)); do
  one ${pairs[i]} & a=$!
  one ${pairs[i + 1]} & b=$!
  wait $a || { echo "record or explanation failed: ${pairs[i]} (logs in $OUT)"; failed=1; }
  wait $b || { echo "record or explanation failed: ${pairs[i + 1]} (logs in $OUT)"; failed=1; }
done
[ "$failed" = 0 ] || exit 1
for p in "${pairs[@]}"; do
  set -- $p
  names+=("s$1_E$2${3:+_$3}")
done
python3 - "$OUT" "${HERTZ_NOISE_PA:-}" "${names[@]}" <<'PY'
import json, sys
out, noisy, bad = sys.argv[1], sys.argv[2] != '', 0
for name in sys.argv[3:]:  # argv: OUT, HERTZ_NOISE_PA (may be empty), the case names
    r = json.load(open(f"{out}/{name}/report.json"))
    soft = '_Esoft' in name
    hertz = '_E0' not in name and not soft
    names = [m['name'] for m in r['mechanisms']]
    line = f"{name}: {r['verdict']}: {names}"
    d = r['dem_confirmation']
    if hertz and noisy and d['status'] != 'done':  # noise may leave the curvature open, never refute Hertz
        bad += d['status'] != 'inconclusive'
        line += f"; DEM: {d['status']} ({d.get('reason', '')[:160]})"
    elif hertz:
        if d['status'] != 'done':
            bad += 1
            line += f"; DEM: {d['status']} ({d.get('reason', '')})"
        else:
            ch = {x['name']: x for x in d['runs']}[d['chosen_run']]
            base = d['runs'][0]
            line += (f"; DEM: unload curvature recording {d['recording_unload_curvature_calibration_branches']:.3f}, linear "
                     f"{base['dem_unload_curvature_calibration_branches']:.3f}, chosen E* {ch['hertz_modulus_Pa']:.3g} Pa "
                     f"({ch['dem_unload_curvature_calibration_branches']:.3f}); held-out reload {d['heldout_rmse_baseline']:.4g} -> "
                     f"{d['heldout_rmse_augmented']:.4g} Pa")
            ctl = {x['name']: x for x in d['runs']}.get(d.get('control_run'))
            if ctl:  # linear contacts as soft as the chosen ones (DemConfirmation.h); the law gated since session 43
                line += (f"; control linear x{ctl['normal_stiffness_scale']:.3g}: curvature "
                         f"{ctl['dem_unload_curvature_calibration_branches']:.3f}, held-out {ctl['heldout_rmse_Pa']:.4g} Pa, "
                         f"law favoured: {d['contact_law_favoured']} (by {d['contact_law_judged_by']}")
                if 'recording_unload_stiffness_exponent' in d:
                    line += (f": recording {d['recording_unload_stiffness_exponent']:.3f}, Hertz "
                             f"{ch.get('dem_unload_stiffness_exponent', float('nan')):.3f}, control "
                             f"{ctl.get('dem_unload_stiffness_exponent', float('nan')):.3f}")
                line += ")"
                bad += d['contact_law_favoured'] != 'hertz' if not noisy else d['contact_law_favoured'] == 'linear_as_soft'
            else:
                bad += 1
                line += "; no control run"
            bad += not noisy and not d['heldout_rmse_augmented'] < d['heldout_rmse_baseline']
    elif soft:  # linear contacts as soft as Hertzian ones at the top: curved, so the surrogate may name the
        # mechanism; the DEM must not favour Hertz's law (the control, linear contacts that soft, is the truth)
        line += f"; DEM: {d['status']}"
        if d['status'] == 'done':
            line += (f"; held-out reload {d['heldout_rmse_baseline']:.4g} -> {d['heldout_rmse_augmented']:.4g} Pa; law favoured: "
                     f"{d.get('contact_law_favoured')} (by {d.get('contact_law_judged_by')})")
            bad += d.get('contact_law_favoured') == 'hertz'
        elif 'stiffness_nonlinearity' in names:
            bad += d['status'] not in (('contradicted', 'inconclusive') if noisy else ('contradicted',))
            line += f" ({d.get('reason', '')[:90]})"
    else:  # the packing alone curves the loading, so the surrogate may name the mechanism; the DEM must refute it
        if 'stiffness_nonlinearity' in names:
            bad += d['status'] not in (('contradicted', 'inconclusive') if noisy else ('contradicted',))
            line += f"; DEM: {d['status']} ({d.get('reason', '')[:90]})"
        else:
            line += f"; DEM: {d['status']}"
    print(line)
sys.exit(1 if bad else 0)
PY
