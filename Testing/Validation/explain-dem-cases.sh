#!/bin/bash
# DEM-made blind-benchmark cases (Tools/Explain/DemCases.h): recordings produced by the project's own
# DEM (OedometerRelaxation, cocoa meso-particles without adhesion, periodic bed) with contact
# relaxation on (peak SNR 3 and 5) or off (nulls), explained with the bed's own behaviour
# (stiffness_nonlinearity, plasticity, loading_curve) in the baseline and scored against the sealed truth.
# PDPM_DEM_CASES (default 4) cases per SNR and as many nulls; about a minute of DEM per run, two
# runs per positive case. Writes summary.md; with --update-doc replaces the measured section of
# Documentation/tools-explain.md. Fails only when a run fails (the figures are reported, not gated).
source "$(dirname "$0")/explain-common.sh"
N="${PDPM_DEM_CASES:-4}"
"$BIN/pdpm-explain-bench" --output "$OUT/dem-cases" --reps 0 --nulls 0 --forced 0 --extras 0 --dem_cases "$N" --dem_snr 3,5 \
  --samples 2000 > "$OUT/dem-cases.log"
python3 - "$OUT/dem-cases/summary.md" <<'PY'
import sys
s = open(sys.argv[1]).read()
print(s[s.index('## DEM-made cases'):])
PY
if [ "${3:-}" = "--update-doc" ]; then
  DOC="$HERE/../../Documentation/tools-explain.md"
  python3 - "$DOC" "$OUT/dem-cases/summary.md" <<'PY'
import sys
doc, summ = open(sys.argv[1]).read(), open(sys.argv[2]).read()
summ = summ[summ.index('## DEM-made cases') + len('## DEM-made cases\n\n'):]
a, b = doc.index('<!-- dem-cases:begin -->'), doc.index('<!-- dem-cases:end -->')
open(sys.argv[1], 'w').write(doc[:a] + '<!-- dem-cases:begin -->\n' + summ + doc[b:])
PY
fi
