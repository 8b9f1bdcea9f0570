#!/usr/bin/env bash
# Validation of OedometerRelaxation against thesis chapter 4 (label: validation; NOT part of the fast
# suite; hours of CPU). Usage: oedometer_validation.sh BUILD_DIR OUT_DIR [THREADS]
#  1. FT4 preset, cocoa, protocol 1, relaxation on: fitted macroscopic C, t0 per hold (from
#     RUN.protocol.json "extra.holds") next to Table 4.4 (FT4 and lambdameter columns).
#  2. Same with --relax_C 0: hold stress constant within 1 %.
#  3. Protocols 1-4 (hold 5/10/20/30 min) on the periodic bed and in the FT4 mould (same seed, so the
#     same poured bed): relative drop after 300 s of each hold (Fig. 4.8 history effect: later steps
#     drop less after longer holds; the first step is unchanged).
#  4. Table 4.4 trend: fitted C per hold of protocol 1 (periodic bed).
#  5. The same history comparison with the relaxation clock memory 0.1 (periodic bed with
#     --relax_memory 0.1; FT4 mould with the ft4 preset, which sets it). Sections 1-3 pass
#     --relax_memory 0 to the ft4 preset: the model without memory.
# Thesis tables are read by path (skipped if absent), never copied into the repository.
set -euo pipefail
BUILD=${1:?build dir}; OUT=${2:?output dir}; THREADS=${3:-2}
EXE="$BUILD/bin/OedometerRelaxation"
DATA=${PDPM_THESIS_DATA:-/work/shared/data/thesis}
mkdir -p "$OUT"
holds() {  # print step, stress_start, stress_end, drop, C, t0 of every hold of a protocol file
  awk 'BEGIN{RS="{"} /"type": "hold_position"/ {
         match($0,/"step": [0-9]+/); s=substr($0,RSTART+8,RLENGTH-8);
         match($0,/"stress_start_Pa": [-0-9.e]+/); a=substr($0,RSTART+19,RLENGTH-19);
         match($0,/"stress_end_Pa": [-0-9.e]+/); b=substr($0,RSTART+17,RLENGTH-17);
         c = match($0,/"fit_C": [-0-9.e]+/) ? sprintf("%.4g", substr($0,RSTART+9,RLENGTH-9)) : "-";  # null: no fit
         t = match($0,/"fit_t0_s": [-0-9.e]+/) ? sprintf("%.4g", substr($0,RSTART+12,RLENGTH-12)) : "-";
         printf "%s %.4g %.4g %.4f %s %s\n", s, a, b, 1-b/a, c, t }' "$1"
}
echo "== 1. FT4 preset, protocol 1, relaxation on"
time "$EXE" --preset ft4 --relax_memory 0 --threads "$THREADS" --output "$OUT" --name ft4_p1 --quiet
echo "step stress_start_Pa stress_end_Pa drop C_fit t0_fit_s"; holds "$OUT/ft4_p1.protocol.json"
[ -f "$DATA/table_4_4_relaxation_devices.csv" ] && { echo "Table 4.4 (thesis):"; grep -v '^#' "$DATA/table_4_4_relaxation_devices.csv"; }
[ -f "$DATA/table_4_5_relaxation_materials.csv" ] && { echo "Table 4.5 (thesis):"; grep -v '^#' "$DATA/table_4_5_relaxation_materials.csv"; }
echo "== 2. FT4 preset, protocol 1, relaxation off (drop must be < 1 %)"
"$EXE" --preset ft4 --relax_memory 0 --relax_C 0 --threads "$THREADS" --output "$OUT" --name ft4_p1_off --quiet
holds "$OUT/ft4_p1_off.protocol.json"
droptable() {  # droptable OUT BED: relative drop 300 s into each hold of BED_p1..4
python3 - "$1" "$2" <<'PY'
import csv, json, sys
out, bed = sys.argv[1], sys.argv[2]
print(f"{bed}: protocol hold_min " + " ".join(f"R{k+1}_drop300s" for k in range(5)) + "  (R_k: relative drop 300 s into hold k)")
for p, mins in zip((1, 2, 3, 4), (5, 10, 20, 30)):
    try:
        proto = json.load(open(f"{out}/{bed}_p{p}.protocol.json"))
        rows = [r for r in csv.reader(l for l in open(f"{out}/{bed}_p{p}.recording.csv") if not l.startswith('#'))]
    except (FileNotFoundError, ValueError):
        print(f"{p} {mins} (missing or unreadable output)")
        continue
    head, rows = rows[0], [list(map(float, r)) for r in rows[1:]]
    it, istep, isx = head.index("time_s"), head.index("step"), head.index("axial_stress_Pa")
    drops = []
    for h in proto["extra"]["holds"]:
        t0, s0 = h["lab_start_s"], h["stress_start_Pa"]
        inside = [r for r in rows if r[istep] == h["step"] and r[it] - t0 <= 300 + 1e-9]
        drops.append(1 - inside[-1][isx] / s0 if inside else float('nan'))
    print(f"{p} {mins} " + " ".join(f"{d:.4f}" for d in drops))
PY
}
echo "== 3. protocols 1-4, periodic bed and FT4 mould: relative stress drop 300 s into each hold (Fig. 4.8)"
for p in 1 2 3 4; do
  "$EXE" --protocol "$p" --width 6 --fill_height 8 --threads "$THREADS" --output "$OUT" --name periodic_p$p --quiet
  [ "$p" = 1 ] && cp "$OUT/ft4_p1.recording.csv" "$OUT/ft4hist_p1.recording.csv" && cp "$OUT/ft4_p1.protocol.json" "$OUT/ft4hist_p1.protocol.json" && continue
  "$EXE" --preset ft4 --relax_memory 0 --protocol "$p" --threads "$THREADS" --output "$OUT" --name ft4hist_p$p --quiet
done
for bed in periodic ft4hist; do droptable "$OUT" "$bed"; done
echo "== 4. Table 4.4 trend: fitted C per hold of protocol 1 (periodic bed)"
holds "$OUT/periodic_p1.protocol.json"
echo "== 5. history effect with the relaxation clock memory 0.1 (periodic bed --relax_memory 0.1 and the ft4 preset, protocols 1-4)"
for p in 1 2 3 4; do
  "$EXE" --protocol "$p" --width 6 --fill_height 8 --relax_memory 0.1 --threads "$THREADS" --output "$OUT" --name periodicmem_p$p --quiet
done
droptable "$OUT" periodicmem
for p in 1 2 3 4; do  # the ft4 preset's own memory, 0.1
  "$EXE" --preset ft4 --protocol "$p" --threads "$THREADS" --output "$OUT" --name ft4mem_p$p --quiet
done
droptable "$OUT" ft4mem
