#!/bin/bash
# Real recording (a): thesis chapter 4 cocoa and limestone relaxation (lambdameter, protocol 1),
# reconstructed from Tables 4.4/4.5. Checks: contact_relaxation named, holds localised, C within
# 25 % of the thesis' C: the thesis fits Eq. 4.3 to each hold separately, so the comparison is the
# report's per-hold fit (mechanisms[].per_hold) against each hold's table value, and their mean against
# the table mean; and the model's own C (the value at its reference stress when it lets C depend on the
# hold stress, else its one C for all holds) against the table's C interpolated (log-log) at that stress;
# and the DEM re-run of contact_relaxation lowers the held-out error by at least 30 %; and neither
# rate_dependence nor wall_friction is named (the reconstruction contains neither; since 2026-12-06).
source "$(dirname "$0")/explain-common.sh"
[ -f "$SHARED/data/thesis/table_4_5_relaxation_materials.csv" ] || { echo "SKIP: thesis tables absent"; exit 77; }
fail=0
for m in cocoa limestone; do
  "$BIN/pdpm-explain-data" thesis --material $m --data "$SHARED/data" --output "$OUT/$m-input" >/dev/null
  "$BIN/pdpm-explain" --recording "$OUT/$m-input/recording.csv" --protocol "$OUT/$m-input/protocol.json" --output "$OUT/$m" >/dev/null
  python3 - "$OUT/$m/report.json" "$OUT/$m-input/thesis-values.json" "$m" <<'PY' || fail=1
import json, sys
r = json.load(open(sys.argv[1])); t = json.load(open(sys.argv[2])); m = sys.argv[3]
names = [x['name'] for x in r['mechanisms']]
ok = 'contact_relaxation' in names
# the reconstruction has relaxation and a curved loading (sigma ~ eps^2) and nothing else: no viscosity
# (rate_dependence is confounded in this one-speed load-and-hold protocol) and no wall friction
spurious = [x for x in names if x in ('rate_dependence', 'wall_friction')]
if spurious: print(f"{m}: names {spurious}, which the reconstruction does not contain")
ok = ok and not spurious
C = None; per = []; sd = {}
for x in r['mechanisms']:
    if x['name'] == 'contact_relaxation':
        C = x['parameters']['C']['value']; ci = x['parameters']['C']['ci95']
        per = [h['C'] for h in x['per_hold']['holds']]
        sd = x['stress_dependence']
holds = sum(w['share_of_excess_residual'] for w in r['windows'] if w['mismatch'] and w['phase'] == 'hold')
acts = sorted({w['phase'] for x in r['mechanisms'] if x['name'] == 'contact_relaxation' for w in x.get('acts_in', [])})
print(f"{m}: verdict {r['verdict']}, mechanisms {names}, C = {C} (95 % {ci if C else '-'}) vs thesis mean {t['C_mean']:.4f}, "
      f"share of excess in hold windows {holds:.2f}, contact_relaxation acts in {acts}")
tab = t['C_per_hold']
def table_at(s):  # the table's C at stress s, log-log interpolation (held flat outside)
    import math
    pts = sorted(zip(t['sigma_max_per_hold_Pa'], t['C_per_hold']))
    if s <= pts[0][0]: return pts[0][1]
    for (s0, c0), (s1, c1) in zip(pts, pts[1:]):
        if s <= s1:
            f = math.log(s / s0) / math.log(s1 / s0)
            return math.exp((1 - f) * math.log(c0) + f * math.log(c1))
    return pts[-1][1]
if C is not None:
    sref = sd['reference_stress_Pa']; ctab = table_at(sref)
    beta = r['mechanisms'][names.index('contact_relaxation')]['parameters'].get('C_stress_exponent', {}).get('value')
    print(f"  model C {C:.4f} ({'at the reference stress %.0f Pa, C ~ sigma_h^(%.3f)' % (sref, -beta) if beta is not None else 'one C for all holds'}; "
          f"stress dependence: {sd['outcome']}): {100 * (C / ctab - 1):+.1f} % against the table's C at {sref:.0f} Pa ({ctab:.4f}), "
          f"{100 * (C / t['C_mean'] - 1):+.0f} % against the table mean")
    ok = ok and abs(C - ctab) <= 0.25 * ctab
    for k, (a, b) in enumerate(zip(per, tab)):
        print(f"  hold {k + 1}: C {a:.4f} vs table {b:.4f} ({100 * (a / b - 1):+.1f} %)")
    mean = sum(per) / len(per) if per else float('nan')
    print(f"  per-hold mean C {mean:.4f} vs table mean {t['C_mean']:.4f} ({100 * (mean / t['C_mean'] - 1):+.1f} %)")
    ok = ok and len(per) == len(tab) and all(abs(a - b) <= 0.25 * b for a, b in zip(per, tab)) \
        and abs(mean - t['C_mean']) <= 0.25 * t['C_mean']
# the DEM re-run (step 6): done, and its held-out error at least 30 % below the DEM without the mechanism
d = r.get('dem_confirmation', {})
if d.get('status') == 'done':
    red = 1 - d['heldout_rmse_augmented'] / d['heldout_rmse_baseline']
    chosen = next((x for x in d['runs'] if x['name'] == d['chosen_run']), {})
    print(f"  DEM confirmation ({d['mechanism']}): held-out {d['heldout_rmse_baseline']:.0f} -> {d['heldout_rmse_augmented']:.0f} Pa "
          f"({100 * red:.1f} % lower), run {d['chosen_run']} (contact C {chosen.get('relax_C', float('nan')):.4f}, "
          f"relaxing in ramps: {chosen.get('relax_in_ramps')})")
    ok = ok and d['mechanism'] == 'contact_relaxation' and red >= 0.30
else:
    print(f"  DEM confirmation: {d.get('status')} ({d.get('reason', '')})")
    ok = False
sys.exit(0 if ok else 1)
PY
done
# Two devices, one material: cocoa in the lambdameter (Table 4.5) and in the FT4 (Table 4.4), explained
# together; check: joint verdict missing_physics naming contact_relaxation, FT4 per-hold C within 25 %
# of Table 4.4 hold by hold, and the joint fit finds that one C cannot serve both devices (the tables
# differ); prints every transfer and joint fit.
"$BIN/pdpm-explain-data" thesis --material cocoa --device ft4 --data "$SHARED/data" --output "$OUT/cocoa-ft4-input" >/dev/null
"$BIN/pdpm-explain" --recording "$OUT/cocoa-input/recording.csv" "$OUT/cocoa-ft4-input/recording.csv" \
  --protocol "$OUT/cocoa-input/protocol.json" "$OUT/cocoa-ft4-input/protocol.json" --output "$OUT/cocoa-two-devices" --dem off >/dev/null
python3 - "$OUT/cocoa-two-devices/report.json" "$OUT/cocoa-ft4-input/thesis-values.json" <<'PY' || fail=1
import json, sys
r = json.load(open(sys.argv[1])); t = json.load(open(sys.argv[2]))
print(f"cocoa lambdameter + FT4: verdict {r['verdict']}; {r['summary']}")
for m in r['mechanisms']:
    vals = '; '.join(f"rec {p['recording']:.0f}: " + ', '.join(f"{k} {v['value']:.4g}" for k, v in p['parameters'].items()) for p in m['per_recording'])
    print(f"  {m['name']}: {m['heldout_recording_status']} ({vals})")
for x in r['heldout_recordings']:
    print(f"  {'+'.join(x['mechanisms'])} from {x['calibrated_on']:.0f} on {x['heldout_recording']:.0f}: RMSE {x['heldout_rmse_baseline']:.1f} -> {x['heldout_rmse_augmented']:.1f} Pa ({-100 * x['gain']:+.1f} %)")
for J in r.get('joint_material_parameters', []):
    vals = ', '.join(f"{k} {v['value']:.4g} ({v['ci95'][0]:.4g} to {v['ci95'][1]:.4g})" for k, v in J['parameters'].items())
    alone = '; '.join(f"rec {x['recording']:.0f}: " + ', '.join(f"{k} {v:.4g}" for k, v in x['parameters'].items()) for x in J['separate'])
    c = J['consistency']
    print(f"  joint {J['mechanism']}: {vals} [{J['intervals']}]; alone {alone}; likelihood ratio {c['likelihood_ratio']:.4g} "
          f"({c['dof']:.0f} dof, p {c['p_value']:.2g}): {c['says']}")
print(f"  thesis FT4 mean C {t['C_mean']:.4f}")
ft4 = json.load(open(sys.argv[1].replace('report.json', 'recording_2/report.json')))
per = []
for m in ft4['mechanisms']:
    if m['name'] == 'contact_relaxation':
        per = [h['C'] for h in m['per_hold']['holds']]
        print(f"  FT4 per-hold C {', '.join(f'{c:.4f}' for c in per)} vs table {', '.join(f'{c:.4f}' for c in t['C_per_hold'])}")
ok = r['verdict'] == 'missing_physics' and any(m['name'] == 'contact_relaxation' for m in r['mechanisms'])
ok = ok and not any(m['name'] in ('rate_dependence', 'wall_friction') for m in r['mechanisms'])
ok = ok and len(per) == len(t['C_per_hold']) and all(abs(a - b) <= 0.25 * b for a, b in zip(per, t['C_per_hold']))
# the two tables' C differ by about a factor 2 (lambdameter 0.079 -> 0.056, FT4 0.044 -> 0.019): one
# relaxation C cannot serve both devices, and the joint fit's consistency test must say so
joint = [J for J in r.get('joint_material_parameters', []) if J['mechanism'] == 'contact_relaxation']
ok = ok and len(joint) == 1 and joint[0]['consistency']['says'] == 'inconsistent'
sys.exit(0 if ok else 1)
PY
exit $fail
