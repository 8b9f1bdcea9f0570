#!/usr/bin/env bash
# The tools on real kernel output: the tutorial driver writes VTU snapshots (with a wall file listed
# in the .pvd as part 1) and RUN.fstat; pdpm-cg and pdpm-polar must read them as written, and the
# coarse-grained density profile must show the bed (mass conservation itself is unit-tested).
#   ToolsOnKernelOutput.sh BIN_DIR
set -euo pipefail
bin="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
"$bin/SettlingColumn" --output run --fstat 1 --quiet --threads 1 --time_max 0.15 > run.log
"$bin/pdpm-cg" --input run/SettlingColumn.pvd run/SettlingColumn.fstat --output cg --nz 30 --tmin 0.1 \
  --format csv > cg.log
"$bin/pdpm-polar" --input run/SettlingColumn.fstat --output polar --plot none --layers 4 > polar.log 2> polar.err
[[ -s cg/cg.csv && -s polar/polar_series.csv && -s polar/polar_layers.csv ]] || { echo "FAIL: tool outputs missing"; exit 1; }
# the layer file: 4 rows per analysed block, and contacts in it (the bed touches the bottom layer)
blocks=$(($(wc -l < polar/polar_series.csv) - 1))
rows=$(($(wc -l < polar/polar_layers.csv) - 1))
[[ $rows -eq $((4 * blocks)) ]] || { echo "FAIL: $rows layer rows for $blocks blocks (expected 4 each)"; exit 1; }
awk -F, 'NR == 1 { for (k = 1; k <= NF; ++k) if ($k == "contacts") c = k; next } { n += $c }
         END { exit (c > 0 && n > 0 ? 0 : 1) }' polar/polar_layers.csv || { echo "FAIL: no contacts in the layers"; exit 1; }
# material in the profile: the largest coarse-grained density is that of a packed bed of the
# tutorial's glass (2500 kg/m3): a solid fraction between 0.45 (looser than any settled frictional
# bed, even averaged with the wall layers) and 0.74 (the densest sphere packing); measured 0.579
awk -F, '!/^#/ && NR > 2 { if ($2 > m) m = $2 } END { printf "max rho %.1f kg/m3 (solid fraction %.3f)\n", m, m / 2500;
         exit (m > 0.45 * 2500 && m < 0.74 * 2500 ? 0 : 1) }' cg/cg.csv \
  || { echo "FAIL: the coarse-grained profile's largest density is not that of a packed bed"; exit 1; }
echo "ok: pdpm-cg and pdpm-polar read the kernel's .pvd/.vtu/.fstat"
