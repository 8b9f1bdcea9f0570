#!/bin/bash
# The blind benchmark of pdpm-explain (generator -> explainer -> scorer). Writes summary.md in the
# output folder; with --update-doc also replaces the measured section of Documentation/tools-explain.md.
# PDPM_EXPLAIN_SEEDS="1 2 3" runs the benchmark once per seed (OUT/bench_seedS) and writes
# OUT/pooled.md: every count of the summaries added over the seeds (one seed's 60 cases per SNR make
# a single case worth 1.7 %, so a target near its threshold is judged on the pooled counts), and the
# forced additions' held-out gains case by case. --update-doc then uses the first seed's summary.
# SKIP_RUNS=1 only re-pools the folders already in OUT. PDPM_EXPLAIN_BIC=T runs the explainer with
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
