#!/bin/bash
# The blind benchmark of pdpm-explain (generator -> explainer -> scorer). Writes summary.md in the
# output folder; with --update-doc also replaces the measured section of Documentation/tools-explain.md.
# PDPM_EXPLAIN_SEEDS="1 2 3" runs the benchmark once per seed (OUT/bench_seedS) and writes
# OUT/pooled.md: every count of the summaries added over the seeds (one seed's 60 cases per SNR make
# a single case worth 1.7 %, so a target near its threshold is judged on the pooled counts), and the
# forced additions' held-out gains case by case. --update-doc then uses the first seed's summary.
# SKIP_RUNS=1 only re-pools the folders already in OUT. Fails when a met target is lost (gate at the end). PDPM_EXPLAIN_BIC=T runs the explainer with
# the acceptance threshold dBIC >= T instead of 10 (the threshold's trade-off).
source "$(dirname "$0")/explain-common.sh"
REPS="${PDPM_EXPLAIN_REPS:-10}"; NULLS="${PDPM_EXPLAIN_NULLS:-100}"
SEEDS="${PDPM_EXPLAIN_SEEDS:-}"
BIC="${PDPM_EXPLAIN_BIC:-10}"
bench() {  # output folder, seed
  "$BIN/pdpm-explain-bench" --output "$1" --reps "$REPS" --nulls "$NULLS" --forced 20 --extras 10 --samples 2000 \
    --snr 0.5,1,2,3,5 --seed "$2" --bic_threshold "$BIC" | tail -5
}
if [ -z "$SEEDS" ]; then
  bench "$OUT/bench" 1
  SUMMARY="$OUT/bench/summary.md"
else
  dirs=()
  for s in $SEEDS; do
    [ "${SKIP_RUNS:-0}" = 1 ] || bench "$OUT/bench_seed$s" "$s"
    dirs+=("$OUT/bench_seed$s")
  done
  [ "${#dirs[@]}" -gt 0 ] || { echo "explain-benchmark.sh: PDPM_EXPLAIN_SEEDS names no seed" >&2; exit 2; }
  SUMMARY="${dirs[0]}/summary.md"
  python3 - "$OUT/pooled.md" "${dirs[@]}" <<'PY'
import json, os, re, sys
out, dirs = sys.argv[1], sys.argv[2:]
rows, order, power, porder = {}, [], {}, []
for d in dirs:
    for line in open(os.path.join(d, 'summary.md')):
        cells = [c.strip() for c in line.strip().strip('|').split('|')]
        if len(cells) == 3 and re.fullmatch(r'\d+/\d+ \([\d.]+ %\)', cells[2]):
            k, n = map(int, cells[2].split()[0].split('/'))
            key = (cells[0], cells[1])
            if key not in rows: rows[key] = [0, 0]; order.append(key)
            rows[key][0] += k; rows[key][1] += n
        elif len(cells) == 6 and all(re.fullmatch(r'\d+/\d+', c) for c in cells[1:]):
            if cells[0] not in power: power[cells[0]] = [[0, 0] for _ in range(5)]; porder.append(cells[0])
            for j, c in enumerate(cells[1:]):
                k, n = map(int, c.split('/')); power[cells[0]][j][0] += k; power[cells[0]][j][1] += n
gains = []
for d in dirs:
    rep = os.path.join(d, 'reports')
    for name in sorted(os.listdir(rep)):
        if not name.startswith('forced_'): continue
        f = json.load(open(os.path.join(rep, name, 'report.json')))['fit']
        hb, ha = f['heldout_rmse_baseline'], f['heldout_rmse_augmented']
        gains.append((1 - ha / hb if hb > 0 else 0.0, os.path.basename(d) + '/' + name))
with open(out + '.tmp', 'w') as o:
    o.write(f"Pooled over {len(dirs)} seeds ({', '.join(os.path.basename(d) for d in dirs)}).\n\n")
    o.write('| figure | target | pooled |\n|---|---|---|\n')
    for key in order:
        k, n = rows[key]
        o.write(f"| {key[0]} | {key[1]} | {k}/{n} ({100 * k / max(n, 1):.1f} %) |\n")
    if gains:
        g = sorted(x for x, _ in gains)
        med = 0.5 * (g[(len(g) - 1) // 2] + g[len(g) // 2])
        over = [(x, c) for x, c in gains if x > 0.02]
        o.write(f"| forced addition on null cases: held-out gain mean / median / max | <= 2 % | "
                f"{100 * sum(g) / len(g):.2f} % / {100 * med:.2f} % / {100 * g[-1]:.2f} % ({len(g)} cases) |\n")
        o.write(f"| forced additions gaining more than 2 % | - | {len(over)}/{len(g)}"
                + (': ' + ', '.join(f'{c} {100 * x:.1f} %' for x, c in sorted(over, reverse=True)) if over else '') + " |\n")
    o.write('\n| mechanism | SNR 0.5 | SNR 1 | SNR 2 | SNR 3 | SNR 5 |\n|---|---|---|---|---|---|\n')
    for m in porder:
        o.write(f"| {m} | " + ' | '.join(f"{k}/{n}" for k, n in power[m]) + ' |\n')
os.replace(out + '.tmp', out)
print(open(out).read())
PY
fi
if [ "${3:-}" = "--update-doc" ]; then
  DOC="$HERE/../../Documentation/tools-explain.md"
  python3 - "$DOC" "$SUMMARY" <<'PY'
import sys
doc, summ = open(sys.argv[1]).read(), open(sys.argv[2]).read()
a, b = doc.index('<!-- benchmark:begin -->'), doc.index('<!-- benchmark:end -->')
open(sys.argv[1], 'w').write(doc[:a] + '<!-- benchmark:begin -->\n' + summ + doc[b:])
PY
fi
# Gate: the targets this benchmark meets (Documentation/tools-explain.md, "measured") must stay met;
# the two it does not meet on one seed (detection at SNR 5: 58/60 on seed 1, 296/300 pooled; the
# primary parameter within 25 % at SNR 5: 87 % pooled, structural) are printed, not gated.
GATE="$SUMMARY"; [ -n "$SEEDS" ] && GATE="$OUT/pooled.md"
python3 - "$GATE" <<'PY'
import re, sys
gated = {  # row prefix -> (<= or >=, threshold in %)
    "false 'missing physics'": ('<=', 5.0), 'detection at peak SNR 3': ('>=', 90.0),
    'correct mechanism among detections': ('>=', 90.0), 'window IoU >= 0.7 among detections': ('>=', 90.0)}
reported = {'detection at peak SNR 5': ('>=', 98.0), 'primary parameter within 25 % (detections': ('>=', 90.0)}
ok, seen = True, set()
for line in open(sys.argv[1]):
    cells = [c.strip() for c in line.strip().strip('|').split('|')]
    if len(cells) != 3: continue
    m = re.fullmatch(r'(\d+)/(\d+) \(([\d.]+) %\)', cells[2])
    fm = re.match(r'(-?[\d.]+(?:e[-+]?\d+)?) %', cells[2])
    for table, gate in ((gated, True), (reported, False)):
        for key, (op, thr) in table.items():
            if cells[0].startswith(key) and m:
                v = 100 * int(m.group(1)) / max(int(m.group(2)), 1)
                met = v <= thr if op == '<=' else v >= thr
                seen.add(key)
                if gate: ok &= met
                print(f"{'gate' if gate else 'report'}: {cells[0]}: {cells[2]} (target {op} {thr:g} %): {'met' if met else 'NOT met'}")
    if cells[0].startswith('forced addition on null cases') and fm:
        met = float(fm.group(1)) <= 2.0; ok &= met; seen.add('forced')
        print(f"gate: forced addition on nulls, mean held-out gain {fm.group(1)} % (target <= 2 %): {'met' if met else 'NOT met'}")
missing = [k for k in gated if k not in seen] + ([] if 'forced' in seen else ['forced addition'])
if missing: ok = False; print('rows missing from the summary: ' + ', '.join(missing))
sys.exit(0 if ok else 1)
PY

