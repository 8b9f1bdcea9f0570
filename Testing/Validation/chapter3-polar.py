#!/usr/bin/env python3
"""Thesis chapter 3, Sec. 3.4.5 and 3.5 (Fig. 3.14-3.16): directional statistics of the contacts along
the uniaxial cycles that chapter3.sh runs with --fstat 1. For every mu it cuts the test blocks (tau in
[0, 1], matched by time with OUT_DIR/UNI_muX.macro.csv) out of OUT_DIR/UNI_muX.fstat and runs
pdpm-polar on them (axis z):

  * Fig. 3.15: the anisotropy descriptors eps2, eps4, eps6 of P6(theta) (Eq. 3.25; method M1, the fit
    to the constant-bin-width density, the thesis' reference) against eps_dev, loading and unloading;
  * Fig. 3.14 (rows nearest tau = 0, 0.5, 1): the normal-force pdf f* = f_n/<f_n>_all in cones
    |n.e_a| > chi = 0.8 around x, y, z and for all contacts (mean, weak share f* < 1, spread, 95th
    percentile, peak height of the density); for every mu the summary columns (spread of the cone means
    at the start; z against the mean of x and y at tau = 0.5 and 1), the full table for SNAP_MUS;
  * Fig. 3.16 (SNAP_MUS, rows nearest tau = 0, 0.25, 0.5, 0.75, 1): the polar distributions P(theta),
    f_n(theta), f_t(theta), psi_t(theta) of the constant-bin-width method, with second- and sixth-order
    harmonic fits (least squares on the bins of [0, pi/2], weighted by the contacts per bin, so that the
    sparse bins at the pole do not dominate): the second-order anisotropy e2, both R^2, and where the
    sixth-order fit is largest and whether it dips at pi/2.

Usage: chapter3-polar.py BIN_DIR OUT_DIR MU [MU ...]
  BIN_DIR holds pdpm-polar; SNAP_MUS="0.1" (default) picks the mu whose snapshots are analysed.
Writes OUT_DIR/ch3_polar.csv (one row per mu), OUT_DIR/ch3_polar_snap_muX.csv (one row per snapshot),
OUT_DIR/ch3_eps_muX.dat, OUT_DIR/ch3_pdf_muX_tauT.dat, OUT_DIR/ch3_bins_muX_tauT.dat and, with gnuplot,
OUT_DIR/ch3_fig3_14.png, ch3_fig3_15.png, ch3_fig3_16.png and ch3_fig3_17.png (the tau = 0.5 distributions of
Fig. 3.16 as surfaces of revolution about z, each divided by its mean: OUT_DIR/ch3_fig3_17_muX.dat). Reported, not gated: the exit code is 0
unless no run could be analysed (1) or the command line is wrong (2).
"""
import csv
import math
import os
import subprocess
import sys

from ch3common import check_mus, cycle_rows, row_at_time, run_gnuplot, usage, write_table

CHI = 0.8
SNAP_TAUS = (0.0, 0.25, 0.5, 0.75, 1.0)
PDF_TAUS = (0.0, 0.5, 1.0)


def cut_blocks(fstat, rows, test_path, snap_rows):
    """Writes the blocks of the cycle to test_path; returns {row index: contact lines} for snap_rows, the
    list of macro row indices of the blocks written (in file order) and {row index: '# box' line}."""
    snaps, order, boxes = {}, [], {}
    keep = False
    cur = None
    tmp = test_path + ".tmp"
    with open(fstat) as f, open(tmp, "w") as out:
        for line in f:
            if line.startswith("# time"):
                parts = line.split()
                k = row_at_time(float(parts[2]), rows)
                keep = k is not None
                cur = k
                if keep:
                    order.append(k)
                    out.write(line)
                    if k in snap_rows:
                        snaps[k] = []
                continue
            if not keep:
                continue
            out.write(line)
            if cur in snaps:
                if line.startswith("# box"):
                    boxes[cur] = line
                elif not line.startswith("#"):
                    snaps[cur].append(line)
    os.replace(tmp, test_path)
    return snaps, order, boxes


def run_polar(bin_dir, inputs, out, name, mu):
    cmd = [os.path.join(bin_dir, "pdpm-polar"), "--input", *inputs, "--output", out, "--name", name, "--axis", "z",
           "--mu", repr(mu if mu > 0 else 0.5), "--plot", "none"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise ValueError("pdpm-polar failed: " + (r.stderr.strip().splitlines() or ["?"])[-1])


def read_csv(path):
    """Rows of a pdpm-polar CSV (its '#' comment lines skipped)."""
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def cone_stats(lines):
    """Normal-force statistics in cones around x, y, z (|n_a| > CHI) and for all contacts, forces in units
    of the mean normal force of all contacts."""
    n, fn = [], []
    for line in lines:
        p = line.split()
        n.append((float(p[6]), float(p[7]), float(p[8])))
        fn.append(float(p[9]))
    if not fn:
        raise ValueError("snapshot without contacts")
    mean_all = sum(fn) / len(fn)
    if not mean_all > 0:
        raise ValueError("snapshot without compressive normal forces")
    res = {}
    for label, sel in (("x", 0), ("y", 1), ("z", 2), ("all", None)):
        f = sorted(fi / mean_all for fi, ni in zip(fn, n) if sel is None or abs(ni[sel]) > CHI)
        c = len(f)
        if c == 0:
            res[label] = dict(count=0, mean=math.nan, weak=math.nan, sd=math.nan, p95=math.nan, peak=math.nan, hist=[])
            continue
        m = sum(f) / c
        sd = math.sqrt(sum((x - m) ** 2 for x in f) / max(1, c - 1))
        width, bins = 0.1, 50
        hist = [0] * bins
        for x in f:
            if 0 <= x < width * bins:
                hist[int(x / width)] += 1
        dens = [h / (c * width) for h in hist]
        res[label] = dict(count=c, mean=m, weak=sum(1 for x in f if x < 1) / c, sd=sd,
                          p95=f[min(c - 1, int(0.95 * c))], peak=max(dens), hist=dens)
    return res


def solve(a, b):
    """Gaussian elimination with partial pivoting (small dense systems)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        if m[c][c] == 0:
            raise ValueError("singular fit")
        for r in range(n):
            if r != c:
                q = m[r][c] / m[c][c]
                m[r] = [x - q * y for x, y in zip(m[r], m[c])]
    return [m[i][n] / m[i][i] for i in range(n)]


def harmonic_fit(theta, y, w, order):
    """Weighted least squares y ~ b0 + b2 Y2 (+ b4 Y4 + b6 Y6 for order 6), weights w (the contacts per
    bin: the pole bins hold few contacts and would otherwise dominate); returns (coefficients, R^2)."""
    def basis(t):
        c = math.cos(t)
        v = [1.0, 3 * c * c - 1]
        if order == 6:
            v += [35 * c ** 4 - 30 * c * c + 3, 231 * c ** 6 - 315 * c ** 4 + 105 * c * c - 5]
        return v
    X = [basis(t) for t in theta]
    k = len(X[0])
    ata = [[sum(w[i] * X[i][a] * X[i][b] for i in range(len(X))) for b in range(k)] for a in range(k)]
    aty = [sum(w[i] * X[i][a] * y[i] for i in range(len(X))) for a in range(k)]
    beta = solve(ata, aty)
    fit = [sum(b * x for b, x in zip(beta, row)) for row in X]
    sw = sum(w)
    mean = sum(wi * v for wi, v in zip(w, y)) / sw
    ss = sum(wi * (v - mean) ** 2 for wi, v in zip(w, y))
    rss = sum(wi * (v - f) ** 2 for wi, v, f in zip(w, y, fit))
    return beta, (1 - rss / ss) if ss > 0 else math.nan


def harmonic_value(beta, t):
    c = math.cos(t)
    ys = [1.0, 3 * c * c - 1, 35 * c ** 4 - 30 * c * c + 3, 231 * c ** 6 - 315 * c ** 4 + 105 * c * c - 5]
    return sum(b * y for b, y in zip(beta, ys))


POLAR_KEYS = ("e2", "R2_2", "R2_6", "peak6_deg", "dip6")


def polar_metrics(bins_csv, friction):
    """Shape of P, f_n, f_t, psi over theta in [0, pi/2] (constant-bin-width bins, weighted by their
    contacts): the second-order anisotropy e2 = b2/b0 of q(theta) = b0 [1 + e2 (3 cos^2 - 1)] (> 0: larger
    along the axis), R^2 of the 2nd- and 6th-order fits, the angle of the 6th-order fit's largest value in
    [0, 90] degrees and its value at 90 degrees over that largest value (< 1: a dip at pi/2)."""
    rows = [r for r in read_csv(bins_csv) if r["method"] == "b" and float(r["theta"]) <= math.pi / 2 + 1e-12]
    rows.sort(key=lambda r: float(r["theta"]))
    out = {}
    for q in ("P", "fn", "ft", "psi"):
        ok = [(float(r["theta"]), float(r[q]), float(r["count"])) for r in rows]
        ok = [x for x in ok if x[1] == x[1] and x[2] > 0]
        if len(ok) < 8 or (q in ("ft", "psi") and not friction):
            out.update({f"{q}_{k}": math.nan for k in POLAR_KEYS})
            continue
        tt, yy, ww = zip(*ok)
        b2, r2 = harmonic_fit(tt, yy, ww, 2)
        b6, r6 = harmonic_fit(tt, yy, ww, 6)
        grid = [math.radians(0.5 * g) for g in range(181)]
        vals = [harmonic_value(b6, t) for t in grid]
        top = max(range(len(vals)), key=lambda g: vals[g])
        out[f"{q}_e2"] = b2[1] / b2[0] if b2[0] != 0 else math.nan
        out[f"{q}_R2_2"] = r2
        out[f"{q}_R2_6"] = r6
        out[f"{q}_peak6_deg"] = 0.5 * top
        out[f"{q}_dip6"] = vals[-1] / vals[top] if vals[top] > 0 else math.nan
    return out


def cone_summary(cones_by_tau):
    """The Fig. 3.14 statements in numbers, for any mu: spread of the cone means at the start; z against
    the lateral cones at the largest compression and at the end."""
    def lat(c, q):
        return 0.5 * (c["x"][q] + c["y"][q])
    res = {}
    c0 = cones_by_tau.get(0.0)
    res["cone_mean_spread_tau0"] = (max(c0[a]["mean"] for a in "xyz") - min(c0[a]["mean"] for a in "xyz")) if c0 else math.nan
    for t, tag in ((0.5, "tau05"), (1.0, "tau1")):
        c = cones_by_tau.get(t)
        res[f"z_over_xy_mean_{tag}"] = c["z"]["mean"] / lat(c, "mean") if c else math.nan
        res[f"weak_z_minus_xy_{tag}"] = c["z"]["weak"] - lat(c, "weak") if c else math.nan
        res[f"z_over_xy_count_{tag}"] = c["z"]["count"] / lat(c, "count") if c else math.nan
    return res


def analyse(bin_dir, out, mu_s, snap):
    mu = float(mu_s)
    macro = f"{out}/UNI_mu{mu_s}.macro.csv"
    fstat = f"{out}/UNI_mu{mu_s}.fstat"
    rows = cycle_rows(macro)
    pdir = f"{out}/polar"
    os.makedirs(pdir, exist_ok=True)
    targets = sorted(set(SNAP_TAUS + PDF_TAUS)) if snap else list(PDF_TAUS)
    target_row = {t: min(range(len(rows)), key=lambda k: abs(rows[k][1] - t)) for t in targets}
    test = f"{pdir}/UNI_mu{mu_s}.cycle.fstat"
    snaps, order, boxes = cut_blocks(fstat, rows, test, set(target_row.values()))
    try:
        if len(order) < 5:
            raise ValueError("fewer than 5 blocks of the cycle in the fstat file")
        run_polar(bin_dir, [test], pdir, f"UNI_mu{mu_s}", mu)
    finally:
        os.remove(test)  # a copy of the cycle's blocks (GBs at full size)
    series = read_csv(f"{pdir}/UNI_mu{mu_s}_series.csv")
    if len(series) != len(order):
        raise ValueError("pdpm-polar skipped blocks (empty?)")
    pts = []  # tau, eps_dev, eps2, eps4, eps6 (M1), se2, se4, se6, eps2 (M2), eps2 from the fabric, eps2 (M3)
    for k, s in zip(order, series):
        _, tau, ed = rows[k]
        pts.append((tau, ed, float(s["M1_eps2"]), float(s["M1_eps4"]), float(s["M1_eps6"]), float(s["M1_se2"]),
                    float(s["M1_se4"]), float(s["M1_se6"]), float(s["M2_eps2"]), float(s["eps2_fabric"]),
                    float(s["M3_eps2"])))
    tmp = f"{out}/ch3_eps_mu{mu_s}.dat.tmp"
    with open(tmp, "w") as f:
        f.write("# tau eps_dev eps2 eps4 eps6 se2 se4 se6 eps2_M2 eps2_fabric eps2_M3   (M1 unless named)\n")
        for p in pts:
            f.write(" ".join(f"{v:.6g}" for v in p) + "\n")
    os.replace(tmp, f"{out}/ch3_eps_mu{mu_s}.dat")
    load = [p for p in pts if p[0] <= 0.5 + 1e-9]
    unload = [p for p in pts if p[0] >= 0.5 - 1e-9]
    first, vmax, last = pts[0], min(pts, key=lambda p: abs(p[0] - 0.5)), pts[-1]
    best = max(load, key=lambda p: p[2])
    e6 = [p[4] for p in pts]
    e6m = sum(e6) / len(e6)
    res = {
        "eps2_start": first[2], "eps2_max_load": best[2], "eps2_rise_load": best[2] - first[2],
        "eps_dev_at_eps2_max": best[1], "eps2_vmax": vmax[2], "eps2_end": last[2],
        "eps4_start": first[3], "eps4_min_load": min(p[3] for p in load), "eps4_vmax": vmax[3],
        "eps4_end": last[3], "eps4_max_unload": max(p[3] for p in unload),
        "eps6_mean": e6m, "eps6_sd": math.sqrt(sum((x - e6m) ** 2 for x in e6) / max(1, len(e6) - 1)),
        "se2_typ": sorted(p[5] for p in pts)[len(pts) // 2], "se4_typ": sorted(p[6] for p in pts)[len(pts) // 2],
        "se6_typ": sorted(p[7] for p in pts)[len(pts) // 2],
        "max_abs_M1_minus_fabric": max(abs(p[2] - p[9]) for p in pts),
        "max_abs_M1_minus_M2": max(abs(p[2] - p[8]) for p in pts),
        "max_abs_M1_minus_M3": max(abs(p[2] - p[10]) for p in pts),
    }
    cones_by_tau, snap_res = {}, []
    for t in targets:
        k = target_row[t]
        if k not in snaps or k not in boxes:
            continue
        cones = cone_stats(snaps[k])
        if t in PDF_TAUS:
            cones_by_tau[t] = cones
        if not snap:
            continue
        tag = f"mu{mu_s}_tau{t:g}"
        try:
            one = f"{pdir}/UNI_{tag}.fstat"
            with open(one + ".tmp", "w") as f:
                f.write(f"# time {rows[k][0]!r} step 0 contacts {len(snaps[k])}\n")
                f.write(boxes[k])
                f.writelines(snaps[k])
            os.replace(one + ".tmp", one)
            run_polar(bin_dir, [one], pdir, f"UNI_{tag}", mu)
            pm = polar_metrics(f"{pdir}/UNI_{tag}_bins.csv", mu > 0)
            with open(f"{out}/ch3_bins_{tag}.dat.tmp", "w") as f:
                f.write("# theta P fn ft psi P6_M1   (constant bin width, theta over [0, pi])\n")
                for r in sorted(read_csv(f"{pdir}/UNI_{tag}_bins.csv"), key=lambda r: float(r["theta"])):
                    if r["method"] == "b":
                        f.write(" ".join(r[c] for c in ("theta", "P", "fn", "ft", "psi", "P6_M1")) + "\n")
            os.replace(f"{out}/ch3_bins_{tag}.dat.tmp", f"{out}/ch3_bins_{tag}.dat")
        except (ValueError, KeyError, OSError, IndexError, ZeroDivisionError, csv.Error) as e:
            print(f"mu = {mu_s}, tau = {t:g}: snapshot left out ({e})")
            continue
        if t in PDF_TAUS:
            with open(f"{out}/ch3_pdf_{tag}.dat.tmp", "w") as f:
                f.write("# fstar P_x P_y P_z P_all  (chi = %g, bins of 0.1)\n" % CHI)
                for b in range(50):
                    f.write(f"{0.1 * b + 0.05:.3f} " + " ".join(
                        f"{cones[c]['hist'][b]:.6g}" if cones[c]["hist"] else "nan" for c in ("x", "y", "z", "all")) + "\n")
            os.replace(f"{out}/ch3_pdf_{tag}.dat.tmp", f"{out}/ch3_pdf_{tag}.dat")
        row = {"tau_target": t, "tau": rows[k][1], "eps_dev": rows[k][2], "contacts": len(snaps[k])}
        for c in ("x", "y", "z", "all"):
            for q in ("count", "mean", "weak", "sd", "p95", "peak"):
                row[f"{c}_{q}"] = cones[c][q]
        row.update(pm)
        snap_res.append(row)
    res.update(cone_summary(cones_by_tau))
    if snap_res:
        keys = list(snap_res[0].keys())
        path = f"{out}/ch3_polar_snap_mu{mu_s}.csv"
        with open(path + ".tmp", "w") as f:
            f.write(",".join(keys) + "\n")
            for r in snap_res:
                f.write(",".join(f"{r.get(k, math.nan):.6g}" for k in keys) + "\n")
        os.replace(path + ".tmp", path)
    return res, snap_res


def print_snapshots(mu_s, snap):
    print(f"\nmu = {mu_s}: normal-force pdf in cones |n.e| > {CHI} (Fig. 3.14; f* = f_n/<f_n>_all)")
    print(f"{'tau':>5} {'cone':>4} {'count':>6} {'mean f*':>8} {'f*<1':>6} {'sd':>6} {'p95':>6} {'peak P':>7}")
    for r in snap:
        if r["tau_target"] not in PDF_TAUS:
            continue
        for c in ("x", "y", "z", "all"):
            print(f"{r['tau']:5.2f} {c:>4} {r[c + '_count']:6.0f} {r[c + '_mean']:8.3f} {r[c + '_weak']:6.3f} "
                  f"{r[c + '_sd']:6.3f} {r[c + '_p95']:6.3f} {r[c + '_peak']:7.3f}")
    print(f"\nmu = {mu_s}: polar distributions (Fig. 3.16), fits weighted by the contacts per bin: e2 of the "
          "2nd-order fit (> 0: larger along z), R^2 of the 2nd / 6th-order fits, angle (deg) of the 6th-order "
          "fit's largest value in [0, 90] and its value at 90 deg relative to that")
    print(f"{'tau':>5} " + " ".join(f"{q + ': e2  R2 2/6  peak  dip':>30}" for q in ("P", "fn", "ft", "psi")))
    for r in snap:
        cells = []
        for q in ("P", "fn", "ft", "psi"):
            g = lambda k: r.get(f"{q}_{k}", math.nan)
            cells.append(f"{g('e2'):8.3f} {g('R2_2'):5.2f}/{g('R2_6'):4.2f} {g('peak6_deg'):5.1f} {g('dip6'):5.2f}")
        print(f"{r['tau']:5.2f} " + " ".join(f"{c:>30}" for c in cells))


def revolution_surface(bins_dat, path, n_phi=48):
    """Fig. 3.17: the polar distributions of one snapshot as surfaces of revolution about z, each
    quantity divided by its mean over the bins (its shape, not its size): for every theta bin and
    azimuth phi the point r (sin theta cos phi, sin theta sin phi, cos theta) and r, one gnuplot splot
    block per quantity (P, f_n, f_t, psi_t), blocks separated by two blank lines. False without bins."""
    rows = []
    with open(bins_dat) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            rows.append([float(x) for x in line.split()[:5]])
    if not rows:
        return False
    # close the surface at the poles: the first and last bins are extended to theta = 0 and pi
    rows = [[0.0] + rows[0][1:]] + rows + [[math.pi] + rows[-1][1:]]
    with open(path, "w") as out:
        out.write("# x y z r  (r = quantity / its mean over the bins; blocks: P, f_n, f_t, psi_t)\n")
        for col in (1, 2, 3, 4):
            mean = sum(r[col] for r in rows[1:-1]) / (len(rows) - 2)
            for r in rows:
                rad = r[col] / mean if mean > 0 else 0.0
                for k in range(n_phi + 1):
                    phi = 2 * math.pi * k / n_phi
                    out.write(f"{rad * math.sin(r[0]) * math.cos(phi):.6g} {rad * math.sin(r[0]) * math.sin(phi):.6g} "
                              f"{rad * math.cos(r[0]):.6g} {rad:.6g}\n")
                out.write("\n")
            out.write("\n")
    return True


def plots(out, mus, snap_mus):
    cols = {2: "eps_2", 3: "eps_4", 4: "eps_6"}
    gp = ["set terminal pngcairo size 1500,1100 noenhanced", f"set output '{out}/ch3_fig3_15.png'", "set multiplot layout 3,2",
          "set key outside right font ',8'", "set xlabel 'eps_dev'"]
    for c, label in cols.items():
        for half, cond in (("loading", "$1<=0.5"), ("unloading", "$1>=0.5")):
            gp.append(f"set ylabel '{label}'; set title '{label}, {half}'")
            gp.append("plot " + ", ".join(
                f"'{out}/ch3_eps_mu{m}.dat' u ({cond}?$2:1/0):{c + 1} w l t 'mu={m}'" for m in mus))
    gp.append("unset multiplot")
    for m in snap_mus:
        pdfs = [t for t in PDF_TAUS if os.path.exists(f"{out}/ch3_pdf_mu{m}_tau{t:g}.dat")]
        if pdfs:
            gp += ["set terminal pngcairo size 1500,450 noenhanced", f"set output '{out}/ch3_fig3_14.png'",
                   f"set multiplot layout 1,{len(pdfs)}", "set logscale y", "set yrange [1e-3:*]", "set xrange [0:5]",
                   "set xlabel 'f/<f_all>'", "set ylabel 'P'", "set key top right"]
            for t in pdfs:
                f = f"{out}/ch3_pdf_mu{m}_tau{t:g}.dat"
                gp.append(f"set title 'mu = {m}, tau = {t:g}, chi = {CHI}'")
                gp.append(f"plot '{f}' u 1:2 w lp t 'x', '' u 1:3 w lp t 'y', '' u 1:4 w lp t 'z', '' u 1:5 w l lw 2 t 'all'")
            gp += ["unset multiplot", "unset logscale y", "set yrange [*:*]", "set xrange [*:*]"]
        snaps = [t for t in SNAP_TAUS if os.path.exists(f"{out}/ch3_bins_mu{m}_tau{t:g}.dat")]
        if snaps:
            gp += ["set terminal pngcairo size 1400,1100 noenhanced", f"set output '{out}/ch3_fig3_16.png'",
                   "set multiplot layout 2,2", "set polar", "set angles radians", "set size square",
                   "unset xlabel", "unset ylabel", "set grid polar", "set key outside right font ',8'",
                   "unset border", "unset xtics", "unset ytics", "set theta top clockwise"]
            for col, label in ((2, "contacts P(theta)"), (3, "normal force f_n(theta) (N)"),
                               (4, "tangential force f_t(theta) (N)"), (5, "mobilised friction psi_t(theta)")):
                gp.append(f"set title 'mu = {m}: {label}'")
                gp.append("plot " + ", ".join(
                    f"'{out}/ch3_bins_mu{m}_tau{t:g}.dat' u 1:{col} w l t 'tau={t:g}'" for t in snaps))
            gp += ["unset multiplot", "unset polar"]
        surf = f"{out}/ch3_fig3_17_mu{m}.dat"
        if os.path.exists(f"{out}/ch3_bins_mu{m}_tau0.5.dat") and revolution_surface(f"{out}/ch3_bins_mu{m}_tau0.5.dat", surf):
            gp += ["set terminal pngcairo size 1400,1200 noenhanced", f"set output '{out}/ch3_fig3_17.png'",
                   "set multiplot layout 2,2", "set view equal xyz", "set view 75, 30", "unset key", "set pm3d depthorder",
                   "set palette rgbformulae 33,13,10", "set ticslevel 0", "set xlabel 'x'", "set ylabel 'y'", "set zlabel 'z'",
                   "set xtics 0.5 font ',8'", "set ytics 0.5 font ',8'", "set ztics 0.5 font ',8'",
                   "set xrange [-1.5:1.5]", "set yrange [-1.5:1.5]", "set zrange [-1.5:1.5]"]
            for k, label in enumerate(("contacts P(theta)", "normal force f_n(theta)", "tangential force f_t(theta)",
                                       "mobilised friction psi_t(theta)")):
                gp.append(f"set title 'mu = {m}, tau = 0.5: {label} / its mean'")
                gp.append(f"splot '{surf}' index {k} u 1:2:3:4 w pm3d")
            gp += ["unset multiplot", "unset pm3d", "unset view", "set xrange [*:*]", "set yrange [*:*]", "set zrange [*:*]"]
    run_gnuplot(gp)


def main():
    if len(sys.argv) < 4:
        usage("usage: chapter3-polar.py BIN_DIR OUT_DIR MU [MU ...]")
    bin_dir, out, mus = sys.argv[1], sys.argv[2], sys.argv[3:]
    if not os.path.isdir(out):
        usage(f"chapter3-polar.py: error: no directory {out}")
    if not os.access(os.path.join(bin_dir, "pdpm-polar"), os.X_OK):
        usage(f"chapter3-polar.py: error: no executable pdpm-polar in {bin_dir}")
    check_mus("chapter3-polar.py", mus)
    snap_mus = os.environ.get("SNAP_MUS", "0.1").split()
    res, done = [], []
    for mu in mus:
        if not os.path.exists(f"{out}/UNI_mu{mu}.fstat") or os.path.exists(f"{out}/UNI_mu{mu}.failed"):
            print(f"mu = {mu}: no UNI_mu{mu}.fstat (run with --fstat 1), left out")
            continue
        try:
            r, snap = analyse(bin_dir, out, mu, mu in snap_mus)
        except (ValueError, KeyError, OSError, IndexError, TypeError, ZeroDivisionError, csv.Error) as e:
            print(f"mu = {mu}: cannot be analysed ({e}), left out")
            continue
        res.append((float(mu), mu, r))
        done.append(mu)
        if snap:
            print_snapshots(mu, snap)
    if not res:
        print("chapter3-polar.py: no run could be analysed")
        return 1
    res.sort()
    print("\nAnisotropy descriptors of P6(theta) (Fig. 3.15, method M1; se*_typ: median standard error of a block)")
    write_table(f"{out}/ch3_polar.csv", res)
    plots(out, [m for _, m, _ in res], [m for m in snap_mus if m in done])
    return 0


if __name__ == "__main__":
    sys.exit(main())
