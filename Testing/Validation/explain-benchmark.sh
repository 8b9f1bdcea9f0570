#!/bin/bash
# The blind benchmark of pdpm-explain (generator -> explainer -> scorer). Writes summary.md in the
# output folder; with --update-doc also replaces the measured section of Documentation/tools-explain.md.
source "$(dirname "$0")/explain-common.sh"
REPS="${PDPM_EXPLAIN_REPS:-10}"; NULLS="${PDPM_EXPLAIN_NULLS:-100}"
"$BIN/pdpm-explain-bench" --output "$OUT/bench" --reps "$REPS" --nulls "$NULLS" --forced 20 --extras 10 --samples 2000 --snr 0.5,1,2,3,5 | tail -5
if [ "${3:-}" = "--update-doc" ]; then
  DOC="$HERE/../../Documentation/tools-explain.md"
  python3 - "$DOC" "$OUT/bench/summary.md" <<'PY'
import sys
doc, summ = open(sys.argv[1]).read(), open(sys.argv[2]).read()
a, b = doc.index('<!-- benchmark:begin -->'), doc.index('<!-- benchmark:end -->')
open(sys.argv[1], 'w').write(doc[:a] + '<!-- benchmark:begin -->\n' + summ + doc[b:])
PY
fi
