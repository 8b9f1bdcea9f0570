#!/usr/bin/env bash
# The worked examples of Documentation/tools-coarse-graining.md and tools-polar.md, end to end.
# Usage: ToolsWorkedExample.sh PDPM_CG PDPM_POLAR PDPM_TOOLS_EXAMPLE [KEEP_DIR]
set -eu
CG=$(realpath "$1"); POLAR=$(realpath "$2"); EXAMPLE=$(realpath "$3")
work=${4:-$(mktemp -d)}
[ $# -ge 4 ] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
cd "$work"
"$EXAMPLE" --output data
# 1D vertical profile of the static column (x, y averaged), Gaussian w = 1 mm
"$CG" --input data/column.pvd data/column.fstat --nz 60 --width 1e-3 --output cg --name column
# 3D field for ParaView, Lucy kernel
"$CG" --input data/column_0000.vtu data/column.fstat --nx 8 --ny 8 --nz 60 --kernel lucy --width 1e-3 --output cg --name column3d --format vti
test -s cg/column.csv && test -s cg/column.vti && test -s cg/column3d.vti
# sigma_zz (column sc_zz) at z = 12 mm within 5 % of the weight above: 4x4 columns of 24 spheres, d = 1 mm
awk -F, 'NR>2 && $1>0.0115 && $1<0.0125 { m=1500*3.141592653589793/6*1e-9; ref=16*(24-$1/1e-3)*m*9.81/16e-6;
         r=$23/ref; if (r<0.95 || r>1.05) { print "sigma_zz " $23 " vs " ref; exit 1 } else n++ }
         END { if (!n) exit 1 }' cg/column.csv
"$POLAR" --input data/uniaxial.fstat --output polar --name uni --plot ${PLOT:-none}
test -s polar/uni_series.csv && test -s polar/uni_bins.csv && test -s polar/uni_pdf.csv
test "$(wc -l < polar/uni_series.csv)" -eq 7
echo "worked examples ok in $work"
