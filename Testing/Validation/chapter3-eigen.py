#!/usr/bin/env python3
"""Thesis chapter 3, Sec. 3.4.3 (Fig. 3.5-3.9): eigenvalues, eigenvector angles and shape factors of
the deviatoric stress and fabric, for all, strong and weak contacts, along the uniaxial cycles that
chapter3.sh runs. Reads OUT_DIR/UNI_muX.macro.csv (columns sig_l1..3, sig_theta1..3, sig_Lambda,
fab_*, sig_strong_*, fab_weak_* ...: eigenvalues of the deviator sorted l1 >= l2 >= l3, angles of their
eigenvectors to the compression axis z in degrees, Lambda = l2 / l1; Tools/MicroMacro/MicroMacro.h),
prints one row per mu with the numbers the thesis describes in words, writes OUT_DIR/ch3_eigen.csv and
per-mu plot files OUT_DIR/ch3_eigen_muX.dat (for chapter3.sh's gnuplot figures).

Usage: chapter3-eigen.py OUT_DIR MU [MU ...]   (missing runs are left out)
The figures are reported, not gated: the exit code is 0 unless no run could be read.

What the thesis says (mu = 0.1 for Fig. 3.5/3.6, all mu for Fig. 3.7-3.9):
  * loading: the axial stress eigenvector turns to the compression axis (theta1 -> 0) by eps_dev ~ 0.02
    for every mu; the two lateral eigenvalues are negative and very similar (shape factor -> -1/2);
  * unloading: theta1 of stress starts to turn only after a delay (mu = 0: from eps_dev ~ 0.12 after the
    reversal at 0.16; mu = 0.1: from ~0.10, at 90 deg by ~0.03); the delay grows with mu; the strains
    where theta1 crosses 45 deg, s_dev crosses zero and the stress shape factor crosses zero collapse
    and decrease with mu (Fig. 3.9); the fabric's crossing is "slightly off"; at the end Lambda -> 1;
  * fabric (mu = 0.1): l1 peaks near eps_dev ~ 0.05 and falls towards zero at the largest strain; |l3|
    slightly above |l2| (anisotropy in the lateral plane); theta1 of the fabric stays near 0 at low mu
    (0 ... 0.05) and turns towards 90 deg near the largest compression at high mu (0.2 ... 1);
  * strong contacts: the fabric's theta1 stays near 0 on loading for every mu; weak contacts: stress and
    fabric theta1 mostly at 90 deg on loading, turning towards 0 on unloading.
"""
import csv
import os
import statistics
import sys

from ch3common import analyse_runs, usage, write_table

NAN = float("nan")


def col(rows, name):
    return [float(r[name]) for r in rows]


def first(rows, pred, key="eps_dev"):
    """eps_dev (or `key`) of the first row meeting pred, NaN if none."""
    return next((float(r[key]) for r in rows if pred(r)), NAN)


def settle_strain(load, name, limit):
    """Smallest eps_dev after which `name` stays below `limit` until the end of loading."""
    eps = NAN
    for r in reversed(load):
        if float(r[name]) >= limit:
            break
        eps = float(r["eps_dev"])
    return eps


def mean_last(rows, name, k=5):
    v = col(rows[-k:], name)
    return sum(v) / len(v) if v else NAN


def median_of(rows, f):
    v = [f(r) for r in rows]
    v = [x for x in v if x == x]
    return statistics.median(v) if v else NAN


def analyse(path):
    rows = list(csv.DictReader(open(path)))
    load = [r for r in rows if 0 < float(r["tau"]) <= 0.5]
    unload = [r for r in rows if float(r["tau"]) > 0.5]
    if not load or not unload:
        raise ValueError("no loading or no unloading rows")
    late = [r for r in load if float(r["eps_dev"]) >= 0.03]  # after the initial alignment
    out = {}
    out["theta1_s_settles_at"] = settle_strain(load, "sig_theta1", 10.0)
    out["stress_l2_l3_gap"] = median_of(late, lambda r: abs(float(r["sig_l2"]) - float(r["sig_l3"])) / float(r["sig_l1"])
                                        if float(r["sig_l1"]) > 0 else NAN)
    out["Lambda_s_end_load"] = mean_last(load, "sig_Lambda")
    out["Lambda_f_end_load"] = mean_last(load, "fab_Lambda")
    out["Lambda_s_end_unload"] = mean_last(unload, "sig_Lambda")
    out["Lambda_f_end_unload"] = mean_last(unload, "fab_Lambda")
    # unloading: where the stress eigenvector starts to turn, and the Fig. 3.9 crossings
    out["theta1_s_turns_at"] = first(unload, lambda r: float(r["sig_theta1"]) > 10.0)
    out["theta1_s_45_at"] = first(unload, lambda r: float(r["sig_theta1"]) > 45.0)
    out["theta1_s_90_at"] = first(unload, lambda r: float(r["sig_theta1"]) > 80.0)
    out["s_dev_zero_at"] = first(unload, lambda r: float(r["s_dev_star"]) <= 0)
    out["Lambda_s_zero_at"] = first(unload, lambda r: float(r["sig_Lambda"]) > 0)
    # fabric: signed axial anisotropy; at high mu it is already negative at the reversal
    fstar_rev = float(load[-1]["F_dev_star"])
    out["F_dev_star_at_reversal"] = fstar_rev
    out["F_dev_zero_at"] = first(unload, lambda r: float(r["F_dev_star"]) <= 0) if fstar_rev > 0 else NAN
    early = [r for r in load if float(r["eps_dev"]) <= 0.10]
    pk = max(early, key=lambda r: float(r["fab_l1"]))
    out["fab_l1_peak_at"] = float(pk["eps_dev"])
    out["fab_l1_end_over_peak"] = float(load[-1]["fab_l1"]) / float(pk["fab_l1"]) if float(pk["fab_l1"]) > 0 else NAN
    # lateral-plane anisotropy of the fabric: (|l3| - |l2|) / l1 where both lateral ones are negative
    out["fab_l3_l2_gap"] = median_of(late, lambda r: (abs(float(r["fab_l3"])) - abs(float(r["fab_l2"]))) / float(r["fab_l1"])
                                      if float(r["fab_l2"]) < 0 and float(r["fab_l1"]) > 0 else NAN)
    out["theta1_f_end_load"] = mean_last(load, "fab_theta1")
    out["theta1_f_strong_load"] = median_of(late, lambda r: float(r["fab_strong_theta1"]))
    out["theta1_f_weak_load"] = median_of(late, lambda r: float(r["fab_weak_theta1"]))
    out["theta1_s_weak_load"] = median_of(late, lambda r: float(r["sig_weak_theta1"]))
    out["theta1_f_weak_end_unload"] = mean_last(unload, "fab_weak_theta1")
    out["theta1_s_weak_end_unload"] = mean_last(unload, "sig_weak_theta1")
    return out, rows


def write_plot_file(path, rows):
    """tau eps_dev branch(0 load, 1 unload) then stress and fabric l1..3 (stress / p), theta1..3,
    Lambda, and theta1 of strong / weak contacts (stress, fabric)."""
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# tau eps_dev branch sl1/p sl2/p sl3/p st1 st2 st3 sLambda fl1 fl2 fl3 ft1 ft2 ft3 fLambda "
                "st1_strong st1_weak ft1_strong ft1_weak\n")
        for r in rows:
            tau = float(r["tau"])
            if tau <= 0:
                continue
            p = float(r["p"]) or NAN
            v = [tau, float(r["eps_dev"]), 0 if tau <= 0.5 else 1]
            v += [float(r[f"sig_l{k}"]) / p for k in (1, 2, 3)] + [float(r[f"sig_theta{k}"]) for k in (1, 2, 3)]
            v += [float(r["sig_Lambda"])] + [float(r[f"fab_l{k}"]) for k in (1, 2, 3)]
            v += [float(r[f"fab_theta{k}"]) for k in (1, 2, 3)] + [float(r["fab_Lambda"])]
            v += [float(r[n]) for n in ("sig_strong_theta1", "sig_weak_theta1", "fab_strong_theta1", "fab_weak_theta1")]
            f.write(" ".join(f"{x:.6g}" for x in v) + "\n")
    os.replace(tmp, path)


def main():
    if len(sys.argv) < 3:
        usage("usage: chapter3-eigen.py OUT_DIR MU [MU ...]")
    out_dir = sys.argv[1]

    def one(path, plot):
        a, rows = analyse(path)
        write_plot_file(plot, rows)
        return a

    res = analyse_runs(out_dir, sys.argv[2:], "ch3_eigen_mu", one, "eigen analysis")
    if not res:
        return
    write_table(f"{out_dir}/ch3_eigen.csv", res)
    # the Fig. 3.9 collapse: the three stress-derived crossings of each mu, their largest spread
    three = ("theta1_s_45_at", "s_dev_zero_at", "Lambda_s_zero_at")
    spreads = []
    for _, _, a in res:
        v = [a[k] for k in three if a[k] == a[k]]
        if len(v) == len(three):
            spreads.append(max(v) - min(v))
    print(f"Fig. 3.9: largest spread of the three stress crossings (theta1 = 45 deg, s_dev = 0, Lambda = 0) "
          + (f"over the {len(spreads)} runs where all three exist: {max(spreads):.4f} in eps_dev" if spreads else ": no run has all three"))
    for k in three:
        z = [a[k] for _, _, a in res if a[k] == a[k]]
        mono = all(b <= a_ + 1e-9 for a_, b in zip(z, z[1:]))
        print(f"Fig. 3.9: {k} non-increasing with mu: {mono} ({', '.join(f'{x:.4f}' for x in z)})")


if __name__ == "__main__":
    main()
