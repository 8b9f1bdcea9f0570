#!/usr/bin/env bash
# Builds PowderDPM and runs the demo simulation.
# Usage: scripts/demo.sh [OUTPUT_DIR]   (default: demo-output)
set -euo pipefail
cd "$(dirname "$0")/.."

out="${1:-demo-output}"
scripts/build.sh
if [[ ! -x build/bin/Demo ]]; then
  echo "demo.sh: build/bin/Demo was not built" >&2
  exit 1
fi
build/bin/Demo --output "$out"
# Plots: stress vs volume fraction during isotropic compression, stress vs strain in uniaxial loading.
if command -v gnuplot >/dev/null 2>&1; then
  gnuplot <<GP
set terminal pngcairo size 1100,450 noenhanced
set output "$out/Demo.png"
set datafile separator ","
set multiplot layout 1,2
set xlabel "volume fraction"; set ylabel "pressure p (Pa)"; set logscale y
plot "$out/Demo.macro.csv" using 2:(\$7>0?\$7:1/0) every ::1 with linespoints title "p"
unset logscale y
set xlabel "axial strain eps_zz"; set ylabel "stress (Pa)"
plot "$out/Demo.macro.csv" using 3:6 every ::1 with linespoints title "sigma_zz", "" using 3:4 every ::1 with linespoints title "sigma_xx"
unset multiplot
GP
fi
echo
echo "demo.sh: outputs are in $(cd "$out" && pwd):"
ls -1 "$out" | sed "s/^/  /" | head -n 40 || true
