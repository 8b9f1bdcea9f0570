#!/usr/bin/env bash
# Checks Testing/Validation/packing-order.py (local crystalline order and contact directions from a
# restart file) against what geometry fixes:
# 1. a box-aligned FCC crystal: every particle crystalline, 2/3 of the contacts in the 40-50 degree bin
#    and 1/3 in the 80-90 degree bin, so P = (2/3)/(cos 40 - cos 50) and (1/3)/(cos 80 - cos 90);
# 2. an ideal gas of points (a restart file written here, uniform random positions): no crystalline
#    particle to speak of (below 1 %);
# 3. bad input (missing file, foreign file, unknown flag): exit code 2 and one line.
# python3 is one of the packages scripts/install-deps.sh installs: a missing python3 fails the test.
set -u
script="$1/Testing/Validation/packing-order.py"
command -v python3 >/dev/null || { echo "FAIL: python3 not installed (scripts/install-deps.sh installs it)"; exit 1; }
fail() { echo "FAIL: $*"; exit 1; }
out=$(python3 "$script" --fcc 3) || fail "--fcc 3 exited with $?"
python3 - "$out" <<'PY' || exit 1
import csv, io, math, sys
row = list(csv.DictReader(io.StringIO(sys.argv[1])))[0]
share = lambda a, b: math.cos(math.radians(a)) - math.cos(math.radians(b))
want = {"P_40_50deg": (2 / 3) / share(40, 50), "P_80_90deg": (1 / 3) / share(80, 90)}
ok = int(row["N"]) == 108 and abs(float(row["crystalline_fraction"]) - 1) < 1e-9 \
    and abs(float(row["contacts_per_particle"]) - 12) < 1e-9
for k, v in want.items():
    ok = ok and abs(float(row[k]) - v) < 2e-3 * v
for k in row:
    if k.startswith("P_") and k not in want:
        ok = ok and float(row[k]) == 0
print(f"fcc: crystalline {row['crystalline_fraction']}, P(40-50) {row['P_40_50deg']} (want {want['P_40_50deg']:.3f}), "
      f"P(80-90) {row['P_80_90deg']} (want {want['P_80_90deg']:.3f})")
sys.exit(0 if ok else 1)
PY
python3 - gas.restart <<'PY'
import random, sys
random.seed(7)
L, n = 12.0, 1000
with open(sys.argv[1], "w") as f:
    f.write("PowderDPM-restart 4\nbox 0 0 0 %g %g %g 1 1 1 0 0 0\nwalls 0\nparticles %d\n" % (L, L, L, n))
    for _ in range(n):
        x = [random.uniform(0, L) for _ in range(3)]
        f.write(" ".join(f"{v:.6f}" for v in x) + " 0 0 0" * 4 + " 0.5 0 0\n")
PY
out=$(python3 "$script" gas.restart) || fail "gas.restart exited with $?"
frac=$(echo "$out" | tail -1 | cut -d, -f5)
echo "ideal gas: crystalline fraction $frac"
python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < 0.01 else 1)" "$frac" || fail "ideal gas counted as crystalline ($frac)"
echo "not a restart" > foreign.txt
for args in "missing.restart" "foreign.txt" "--bogus"; do
  msg=$(python3 "$script" $args 2>&1 >/dev/null); rc=$?
  [ $rc -eq 2 ] || fail "'$args': exit code $rc, want 2"
  [ "$(echo "$msg" | wc -l)" -eq 1 ] || fail "'$args': message of more than one line"
  echo "bad input '$args': $msg"
done
echo "PackingOrder: all checks passed"
