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
# the 3D field's content (its .vti is compressed): the same field written as CSV must hold the mass
# of the column, 16 x 24 spheres of d = 1 mm and 1500 kg/m3, as the sum of rho over its 8 x 8 x 60
# cells of 0.5 mm (the coarse-graining conserves mass: measured to 1e-11)
"$CG" --input data/column_0000.vtu data/column.fstat --nx 8 --ny 8 --nz 60 --kernel lucy --width 1e-3 --output cg \
  --name column3d_check --format csv > /dev/null
awk -F, '/^#/ || $1 == "x" { next } { m += $4 * 0.5e-3 ^ 3; ++n }
         END { ref = 384 * 1500 * 3.141592653589793 / 6 * 1e-9; printf "3D field mass %.9g kg vs %.9g kg\n", m, ref;
               exit !(n == 3840 && m > ref * (1 - 1e-6) && m < ref * (1 + 1e-6)) }' cg/column3d_check.csv
# sigma_zz (column sc_zz) at z = 12 mm within 5 % of the weight above: 4x4 columns of 24 spheres, d = 1 mm
awk -F, 'NR>2 && $1>0.0115 && $1<0.0125 { m=1500*3.141592653589793/6*1e-9; ref=16*(24-$1/1e-3)*m*9.81/16e-6;
         r=$23/ref; if (r<0.95 || r>1.05) { print "sigma_zz " $23 " vs " ref; exit 1 } else n++ }
         END { if (!n) exit 1 }' cg/column.csv
"$POLAR" --input data/uniaxial.fstat --output polar --name uni --plot ${PLOT:-none}
test -s polar/uni_series.csv && test -s polar/uni_bins.csv && test -s polar/uni_pdf.csv
test "$(wc -l < polar/uni_series.csv)" -eq 7
# the bins' contents: every contact is counted with n and -n, so each method's fractions add up to 2,
# and P(theta) of the b-bins is a density on the sphere (sum of P sin(theta) dtheta = 1); the force
# pdfs are densities normalised by their cone's contacts, so each integrates to 1 less the tail above
# --pdf_max (5 <f_n>): between 0.9 and 1
awk -F, '/^#/ || $1 == "method" { next } { f[$1] += $7; if ($1 == "b") I += $8 * ($5 - $4) * sin($2) }
         END { ok = (f["b"] > 2 - 1e-6 && f["b"] < 2 + 1e-6 && f["h"] > 2 - 1e-6 && f["h"] < 2 + 1e-6 && I > 0.999 && I < 1.001);
               printf "bins: fractions b %.6f h %.6f (2 each), b-bin P integrates to %.6f (1)\n", f["b"], f["h"], I; exit !ok }' polar/uni_bins.csv
awk -F, '/^#/ || $1 == "fstar" { next } { if (n++ == 0) f0 = $1; else if (n == 2) w = $1 - f0; for (k = 2; k <= 5; ++k) s[k] += $k }
         END { ok = w > 0; for (k = 2; k <= 5; ++k) { i = s[k] * w; printf "pdf column %d integrates to %.4f\n", k, i; ok = ok && i > 0.9 && i <= 1 + 1e-9 }; exit !ok }' polar/uni_pdf.csv
echo "worked examples ok in $work"
