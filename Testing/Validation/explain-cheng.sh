#!/bin/bash
# Real recording (c): the GrainLearning glass-bead oedometer (axial strain control, p and q ->
# axial and lateral stress; the explainer uses the axial stress).
source "$(dirname "$0")/explain-common.sh"
# Sparse record (one point per load step): the noise cannot be estimated from differences, so the
# instrument noise is given: 0.02 MPa (assumed; the file does not state it).
echo '{"noise_sigma_Pa": 20000}' > "$OUT/model-cheng.json"
F="$SHARED/data/external/grainlearning-cheng-exp/oedometer/obsdata.dat"
[ -f "$F" ] || { echo "SKIP: $F absent"; exit 77; }
"$BIN/pdpm-explain-data" import-cheng --input "$F" --output "$OUT/cheng-input"
"$BIN/pdpm-explain" --recording "$OUT/cheng-input/recording.csv" --protocol "$OUT/cheng-input/protocol.json" --model "$OUT/model-cheng.json" --output "$OUT/cheng" >/dev/null
python3 - "$OUT/cheng/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
names = [m['name'] for m in r['mechanisms']]
acts = sorted({w['phase'] for m in r['mechanisms'] if m['name'] == 'plasticity' for w in m.get('acts_in', [])})
f = r['fit']
print(f"glass beads: {r['verdict']}; mechanisms {names}; mismatch in "
      f"{sorted({w['phase'] for w in r['windows'] if w['mismatch']})}; plasticity acts in {acts}; "
      f"held-out RMSE {f['heldout_rmse_baseline']:.4g} -> {f['heldout_rmse_augmented']:.4g} Pa")
# gate (Documentation/tools-explain.md, real recording (c)): the beads are loaded, unloaded and
# reloaded, and the linear-elastic baseline lacks the stiffer unloading: missing_physics naming
# plasticity, acting in the unload or reload branch, with a lower held-out error
ok = r['verdict'] == 'missing_physics' and 'plasticity' in names and bool({'unload', 'reload'} & set(acts)) \
    and f['heldout_rmse_augmented'] < f['heldout_rmse_baseline']
sys.exit(0 if ok else 1)
PY
