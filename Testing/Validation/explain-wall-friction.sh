#!/bin/bash
# Wall friction end to end on records made by the OedometerRelaxation driver itself (the tables of
# Documentation/tools-explain.md, "Bottom stress sensor" and "Wall friction"): load to 15 kPa, unload
# to 1 kPa, reload to 20 kPa, elastic contacts, no adhesion or relaxation, 2.5 mm cocoa
# meso-particles. Records: a 30 mm mould (H/D about 1) with mu_w = 0.3 and fill seeds 1, 2, 3, their
# mu_w = 0 twins, and a 20 mm mould with mu_w = 0.3 (fill seed 777). pdpm-explain reads each record's
# bottom stress sensor; the mu_w = 0.3 records also get the DEM confirmation of wall_friction
# (`--dem fast`, mu_w calibrated on the sensor). With --ft4 the fill-seed-1 record is also confirmed
# at the FT4 size (about 10 min on 2 threads). One thread per run, two runs side by side: about
# 11 min in all. Prints one line per record; fails if a run fails, if the sensor's verdict is wrong
# on any record, or if a mu_w = 0.3 record's DEM confirmation is not done.
source "$(dirname "$0")/explain-common.sh"
FT4="${3:-}"
cat > "$OUT/protocol.json" <<'JSON'
{"format": "pdpm-oedometer-protocol", "version": 1, "source": "experiment",
 "device": {"name": "oedometer", "diameter_m": 0.05, "height_m": 0.05, "wall_friction": 0}, "material": {"name": "cocoa"},
 "steps": [{"type": "ramp", "velocity_m_s": 1e-5, "target_stress_Pa": 15000},
           {"type": "unload", "velocity_m_s": 1e-5, "target_stress_Pa": 1000},
           {"type": "ramp", "velocity_m_s": 1e-5, "target_stress_Pa": 20000}]}
JSON
record() {  # name diameter_m seed mu_w
  "$BIN/OedometerRelaxation" --protocol_file "$OUT/protocol.json" --geometry cylinder --device "mould$2" --diameter "$2" \
    --fill_height_m "$2" --wall_friction "$4" --relax_C 0 --kc_over_k 0 --k_over_k1 1 --ramp_rate 1 --seed "$3" \
    --output "$OUT/records" --name "$1" --quiet --vtk 0 --ene 0 --threads 1 > "$OUT/records-$1.log" 2>&1
}
explain() {  # name dem
  OMP_NUM_THREADS=1 "$BIN/pdpm-explain" --recording "$OUT/records/$1.recording.csv" --protocol "$OUT/records/$1.protocol.json" \
    --output "$OUT/$1" --dem "$2" --dem_threads 1 --no_figures 1 > "$OUT/$1.log" 2>&1
}
pids=()
record d30_s1_mu0.3 0.03 1 0.3 & pids+=($!); record d30_s1_mu0 0.03 1 0 & pids+=($!)
for p in "${pids[@]}"; do wait "$p"; done; pids=()
record d30_s2_mu0.3 0.03 2 0.3 & pids+=($!); record d30_s2_mu0 0.03 2 0 & pids+=($!)
for p in "${pids[@]}"; do wait "$p"; done; pids=()
record d30_s3_mu0.3 0.03 3 0.3 & pids+=($!); record d30_s3_mu0 0.03 3 0 & pids+=($!)
for p in "${pids[@]}"; do wait "$p"; done; pids=()
record d20_s777_mu0.3 0.02 777 0.3
explain d30_s1_mu0.3 fast & pids+=($!); explain d30_s2_mu0.3 fast & pids+=($!)
for p in "${pids[@]}"; do wait "$p"; done; pids=()
explain d30_s3_mu0.3 fast & pids+=($!); explain d20_s777_mu0.3 fast & pids+=($!)
for p in "${pids[@]}"; do wait "$p"; done; pids=()
for s in 1 2 3; do explain d30_s${s}_mu0 off; done
runs="d30_s1_mu0.3 d30_s2_mu0.3 d30_s3_mu0.3 d20_s777_mu0.3 d30_s1_mu0 d30_s2_mu0 d30_s3_mu0"
if [ "$FT4" = "--ft4" ]; then
  OMP_NUM_THREADS=2 "$BIN/pdpm-explain" --recording "$OUT/records/d30_s1_mu0.3.recording.csv" \
    --protocol "$OUT/records/d30_s1_mu0.3.protocol.json" --output "$OUT/ft4_d30_s1_mu0.3" --dem ft4 --dem_threads 2 --no_figures 1 \
    > "$OUT/ft4_d30_s1_mu0.3.log" 2>&1
  runs="$runs ft4_d30_s1_mu0.3"
fi
python3 - "$OUT" $runs <<'PY'
import json, sys
out, bad = sys.argv[1], 0
for name in sys.argv[2:]:
    r = json.load(open(f"{out}/{name}/report.json"))
    b = r.get('bottom_sensor', {})
    mu = 0.0 if name.endswith('_mu0') else 0.3
    want = 'no_wall_loss' if mu == 0 else 'wall_friction_present'
    line = (f"{name}: sensor T {b.get('loading_transmission', float('nan')):.3f} +- {3 * b.get('loading_transmission_se', float('nan')):.3f} "
            f"({b.get('says')}); {r['verdict']}: {[m['name'] for m in r['mechanisms']]}")
    bad += b.get('says') != want
    d = r['dem_confirmation']
    if mu > 0:
        if d['status'] != 'done' or d.get('mechanism') != 'wall_friction':
            bad += 1
            line += f"; DEM: {d['status']} {d.get('mechanism', '')} ({d.get('reason', '')})"
        else:
            ch = {x['name']: x for x in d['runs']}[d['chosen_run']]
            line += (f"; DEM ({d['calibration']}): mu_w {ch['wall_friction']:.3f} (T {ch.get('dem_bottom_over_piston_loading', float('nan')):.3f}), "
                     f"held-out piston {d['heldout_rmse_baseline']:.4g} -> {d['heldout_rmse_augmented']:.4g} Pa, "
                     f"bottom {d.get('heldout_bottom_rmse_baseline', float('nan')):.4g} -> {d.get('heldout_bottom_rmse_augmented', float('nan')):.4g} Pa")
    print(line)
sys.exit(1 if bad else 0)
PY
