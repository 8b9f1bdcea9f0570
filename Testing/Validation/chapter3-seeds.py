#!/usr/bin/env python3
"""Seed scatter of the chapter-3 friction sweep: reads OUT/ch3_summary.csv of several chapter3.sh
runs that differ only in --seed, and prints per mu the s_dev^max of every seed with mean, standard
deviation and standard error, and the paired differences between neighbouring mu (a seed gives the
same initial gas for every mu, so the pairing removes most of the packing-to-packing scatter).

Usage: chapter3-seeds.py OUT_DIR [OUT_DIR ...]   (Documentation/validation-thesis-ch3.md)
"""
import csv
import os
import statistics as st
import sys


def fail(message):  # bad input: one line, exit code 2 (the project's rule)
    print(message, file=sys.stderr)
    sys.exit(2)


if len(sys.argv) < 3:
    fail("usage: chapter3-seeds.py OUT_DIR OUT_DIR [...] (two or more chapter3.sh output folders)")
runs = {}  # mu -> {folder: s_dev_max}
for folder in sys.argv[1:]:
    path = os.path.join(folder, "ch3_summary.csv")
    if not os.path.exists(path):
        fail(f"chapter3-seeds.py: {path} is missing (run chapter3.sh first)")
    with open(path) as f:
        for row in csv.DictReader(f):
            try:
                runs.setdefault(float(row["mu"]), {})[folder] = float(row["s_dev_max"])
            except (KeyError, ValueError):
                fail(f"chapter3-seeds.py: {path} is not a ch3_summary.csv (mu, s_dev_max columns)")


def spread(values):
    sd = st.stdev(values) if len(values) > 1 else float("nan")
    return st.mean(values), sd, sd / len(values) ** 0.5


print(f"{'mu':>5} {'seeds':>5} {'mean s_dev^max':>14} {'sd':>7} {'se':>7}  values")
for mu in sorted(runs):
    v = list(runs[mu].values())
    m, sd, se = spread(v)
    print(f"{mu:5g} {len(v):5d} {m:14.4f} {sd:7.4f} {se:7.4f}  " + " ".join(f"{x:.3f}" for x in v))
mus = sorted(runs)
for a, b in zip(mus, mus[1:]):
    d = [runs[b][k] - runs[a][k] for k in runs[a] if k in runs[b]]
    if len(d) > 1:
        m, sd, se = spread(d)
        print(f"s_dev^max(mu = {b:g}) - s_dev^max(mu = {a:g}), same seeds: n = {len(d)}, mean {m:+.4f}, "
              f"sd {sd:.4f}, se {se:.4f}" + (f" ({m / se:+.1f} se)" if se > 0 else ""))
