#!/usr/bin/env bash
# Thesis chapter 3 (frictional, preset thesis-ch3, mu = 0 ... 1): uniaxial cycles from v_i = 0.692;
# checks the trends of Fig. 3.4 and 3.9: s_dev^max rises with mu up to mu ~ 0.25-0.3, F_dev^max
# decreases with mu, and the strain at which s_dev returns to zero on unloading decreases with mu.
# Usage: chapter3.sh BIN_DIR SOURCE_DIR [THREADS]      (days of CPU time at full scale)
set -euo pipefail
bin="$1"; src="$2"; threads="${3:-2}"
mus="0 0.01 0.02 0.05 0.1 0.2 0.3 0.5 1.0"
for mu in $mus; do
  "$bin/UniaxialCyclic" --preset thesis-ch3 --mu "$mu" --v_i 0.692 --threads "$threads" --quiet --vtk 0 \
    --output ch3 --name "UNI_mu$mu"
done
python3 - $mus <<'PY'
import sys, csv
mus = sys.argv[1:]
print(f"{'mu':>5} {'s_dev_max':>10} {'F_dev_max':>10} {'eps_dev(s_dev~0, unloading)':>28}")
res = []
for mu in mus:
    rows = list(csv.DictReader(open(f"ch3/UNI_mu{mu}.macro.csv")))
    load = [r for r in rows if 0 < float(r['tau']) <= 0.5]
    unload = [r for r in rows if float(r['tau']) > 0.5]
    smax = max(float(r['s_dev']) for r in load); fmax = max(float(r['F_dev']) for r in load)
    # signed s_dev (Eq. 3.19 analogue) changes sign where the stress becomes isotropic
    zero = next((float(r['eps_dev']) for r in unload if float(r['s_dev_star']) <= 0), float('nan'))
    res.append((float(mu), smax, fmax, zero))
    print(f"{mu:>5} {smax:10.4f} {fmax:10.4f} {zero:28.4f}")
ok = True
peak = max(res, key=lambda r: r[1])[0]
print("s_dev_max peaks at mu =", peak); ok &= 0.1 <= peak <= 0.5
ok &= res[-1][2] < res[0][2]; print("F_dev_max decreases with mu:", res[-1][2] < res[0][2])
ok &= res[-1][3] < res[1][3]; print("zero-crossing strain decreases with mu:", res[-1][3] < res[1][3])
sys.exit(0 if ok else 1)
PY
