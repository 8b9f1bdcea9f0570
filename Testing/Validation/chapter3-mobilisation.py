#!/usr/bin/env python3
"""Thesis chapter 3, Sec. 3.4.4 (Fig. 3.11-3.13): weak and strong contacts (f_n below / above the mean
normal force) and their friction mobilisation (sliding: f_t at the Coulomb limit) along the uniaxial
cycles that chapter3.sh runs. Reads OUT_DIR/UNI_muX.macro.csv (columns weak_fraction and f_wsl, f_wst,
f_ssl, f_sst: weak sliding, weak sticking, strong sliding, strong sticking, each a fraction of all
contacts; Tools/MicroMacro/MicroMacro.h), prints one column per frictional mu with the numbers the
thesis describes in words (peaks and minima of wsl/w and sst/s from a 9-row running mean), writes OUT_DIR/ch3_mobilisation.csv and per-mu plot files
OUT_DIR/ch3_mobil_muX.dat (tau, weak fraction, wsl/w, sst/s, wsl/sl, sst/st).

Usage: chapter3-mobilisation.py OUT_DIR MU [MU ...]   (mu = 0 and missing runs are left out)
Reported, not gated: the exit code is 0 unless no frictional run could be read.

What the thesis says:
  * Fig. 3.11a: more than half of the contacts are weak at every mu and time; at the start of loading the
    weak fraction is higher for lower mu; on loading it decreases for low mu and increases for high mu;
    at tau = 0.5 the fractions are close, slightly higher for mu = 0.5 and 1; at the end of unloading
    it is slightly below its start for mu = 0.01, 0.05 and above its start for higher mu;
  * Fig. 3.12a: the share of weak contacts that slide grows on loading, peaks, and falls towards zero at
    tau = 0.5; the peak falls with mu; on unloading a second, higher peak; always well below 50 %;
  * Fig. 3.12b: the share of strong contacts that stick falls on loading to a minimum and rises again
    towards tau = 0.5; "the rate of decrease and the minima reached decrease with increasing friction"
    (read literally: the minimum falls with mu); the minima are lower on unloading;
  * Fig. 3.13: more than half of the sliding contacts are weak; a little less than half of the sticking
    contacts are strong.
"""
import csv
import os
import sys

from ch3common import analyse_runs, usage, extreme, finite, write_table

NAN = float("nan")


def ratio(a, b):
    return a / b if b > 0 else NAN


def series(rows):
    """tau, weak fraction, wsl/w, sst/s, wsl/sl, sst/st for every row of the cycle (tau > 0)."""
    out = []
    for r in rows:
        tau = float(r["tau"])
        if tau <= 0:
            continue
        w = float(r["weak_fraction"])
        wsl, wst, ssl, sst = (float(r[k]) for k in ("f_wsl", "f_wst", "f_ssl", "f_sst"))
        out.append((tau, w, ratio(wsl, wsl + wst), ratio(sst, ssl + sst), ratio(wsl, wsl + ssl), ratio(sst, wst + sst)))
    return out


def smoothed(rows, k, h=4):
    """Column k of each row replaced by its running mean over 2h+1 rows (NaNs skipped): at low mu the
    slip state of a weak contact flickers from one output row to the next, so single-row extremes
    measure that flicker, not the trend the thesis describes."""
    out = []
    for i, x in enumerate(rows):
        win = finite(y[k] for y in rows[max(0, i - h):i + h + 1])
        out.append(x[:k] + (sum(win) / len(win) if win else NAN,) + x[k + 1:])
    return out


def analyse(s):
    load = [x for x in s if x[0] <= 0.5]
    unload = [x for x in s if x[0] > 0.5]
    for k in (2, 3):  # the sliding / sticking shares, within each branch
        load, unload = smoothed(load, k), smoothed(unload, k)
    if len(load) < 5 or len(unload) < 5:
        raise ValueError("too few loading or unloading rows")
    a = {}
    a["weak_min"] = min(x[1] for x in s)
    a["weak_start"] = sum(x[1] for x in load[:3]) / 3
    a["weak_reversal"] = load[-1][1]
    a["weak_end"] = sum(x[1] for x in unload[-3:]) / 3
    a["wsl_w_peak_load"], a["wsl_w_peak_load_tau"] = extreme(load, 2, max)
    a["wsl_w_at_reversal"] = load[-1][2]
    a["wsl_w_peak_unload"] = extreme(unload, 2, max)[0]
    a["sst_s_min_load"], a["sst_s_min_load_tau"] = extreme(load, 3, min)
    a["sst_s_at_reversal"] = load[-1][3]
    a["sst_s_min_unload"] = extreme(unload, 3, min)[0]
    # Fig. 3.13: shares among the sliding / sticking contacts, over the rows where any contact slides
    ws = finite(x[4] for x in s)
    a["wsl_sl_median"] = sorted(ws)[len(ws) // 2] if ws else NAN
    a["wsl_sl_rows_above_half"] = sum(x > 0.5 for x in ws) / len(ws) if ws else NAN
    st = finite(x[5] for x in s)
    a["sst_st_median"] = sorted(st)[len(st) // 2] if st else NAN
    return a


def main():
    if len(sys.argv) < 3:
        usage("usage: chapter3-mobilisation.py OUT_DIR MU [MU ...]")
    out_dir = sys.argv[1]

    def one(path, plot):
        s = series(list(csv.DictReader(open(path))))
        a = analyse(s)
        tmp = plot + ".tmp"
        with open(tmp, "w") as f:
            f.write("# tau weak_fraction wsl/w sst/s wsl/sl sst/st\n")
            for x in s:
                f.write(" ".join(f"{v:.6g}" for v in x) + "\n")
        os.replace(tmp, plot)
        return a

    # frictionless runs are skipped: nothing slides
    res = analyse_runs(out_dir, sys.argv[2:], "ch3_mobil_mu", one, "mobilisation analysis", skip=lambda mu: float(mu) == 0)
    if not res:
        return
    write_table(f"{out_dir}/ch3_mobilisation.csv", res)


if __name__ == "__main__":
    main()
