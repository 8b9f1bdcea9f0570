#!/usr/bin/env bash
# Builds PowderDPM and runs the element-test demo: IsotropicCompression (preparation, isotropic
# loading to v_max = 0.82 and unloading, restart files at v_i) -> UniaxialCyclic from the isotropic
# unloading branch at v = 0.70, both at the fast default preset, then the standard figures via
# pdpm-fit plot (gnuplot) and a Table 2.2-style fit table.
# Usage: scripts/demo.sh [OUTPUT_DIR]   (default: demo-output)
set -euo pipefail
cd "$(dirname "$0")/.."

out="${1:-demo-output}"
scripts/build.sh
for p in IsotropicCompression UniaxialCyclic OedometerRelaxation pdpm-fit pdpm-explain pdpm-explain-data; do
  if [[ ! -x build/bin/$p ]]; then
    echo "demo.sh: build/bin/$p was not built" >&2
    exit 1
  fi
done
mkdir -p "$out"
build/bin/IsotropicCompression --output "$out" --save_fractions 0.70,0.75
build/bin/UniaxialCyclic --output "$out" --start "$out/IsotropicCompression.unload_0.700.restart"
if command -v gnuplot >/dev/null 2>&1; then
  build/bin/pdpm-fit plot --out "$out/plots" "$out/IsotropicCompression.macro.csv" "$out/UniaxialCyclic.macro.csv"
else
  echo "demo.sh: gnuplot not found, no plots (apt-get install gnuplot-nox)" >&2
fi
echo
echo "Fits of Eq. 2.11, 2.12, 2.14 (unloading branches):"
build/bin/pdpm-fit table "$out/IsotropicCompression.macro.csv" "$out/UniaxialCyclic.macro.csv" || true
echo
echo "demo.sh: outputs are in $(cd "$out" && pwd):"
ls -1 "$out" | grep -v '_[0-9]*\.vtu$' | sed "s/^/  /" | head -n 40 || true
echo "  (plus RUN_NNNN.vtu snapshots for ParaView; figures in plots/)"

# pdpm-explain on the thesis' cocoa relaxation recording (lambdameter, protocol 1; reconstructed from
# Tables 4.4/4.5 of ../shared/data/thesis): where does a model without time dependence disagree, and why?
shared="$(cd .. && pwd)/shared"
if [[ -f "$shared/data/thesis/table_4_5_relaxation_materials.csv" ]]; then
  echo "demo.sh: pdpm-explain on the thesis cocoa recording (surrogate fit, then 3 small DEM runs: a few minutes)"
  build/bin/pdpm-explain-data thesis --material cocoa --data "$shared/data" --output "$out/explain-cocoa-input" >/dev/null
  build/bin/pdpm-explain --recording "$out/explain-cocoa-input/recording.csv" \
    --protocol "$out/explain-cocoa-input/protocol.json" --output "$out/explain-cocoa" > "$out/explain-cocoa.log"
  echo
  echo "pdpm-explain on the thesis cocoa recording (report: $out/explain-cocoa/report.md):"
  grep -m1 '"verdict"' "$out/explain-cocoa/report.json" | sed 's/^ */  /' || true
  grep -A3 -m1 -i "^## *verdict\|^\*\*verdict" "$out/explain-cocoa/report.md" | sed 's/^/  /' || true
  grep -m1 "^Mean C over the holds" "$out/explain-cocoa/report.md" | sed 's/^/  /' || true
  grep -m1 "^DEM confirmation" "$out/explain-cocoa.log" | sed 's/^/  /' || true
else
  echo "demo.sh: ../shared/data/thesis not found, skipping pdpm-explain" >&2
fi
