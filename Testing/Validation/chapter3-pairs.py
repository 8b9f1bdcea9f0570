#!/usr/bin/env python3
"""Thesis chapter 3, Sec. 3.4.4 (Fig. 3.10): single contact pairs followed through the uniaxial cycle,
f* = f_n/<f_n> and f_t/(mu f_n) against tau, from OUT_DIR/UNI_muX.fstat of a chapter3.sh run with
--fstat 1 (blocks of the cycle matched by time with OUT_DIR/UNI_muX.macro.csv, tau in [0, 1]).

The thesis shows two pairs "randomly selected from the ensemble", both weak and sliding at the start.
Here every pair in contact at tau = 0 is followed, which turns the two anecdotes into fractions:
  * ws-rule ("sliding is mostly active at weak contacts, while stronger contacts stay in the sticking
    regime"): share of the samples (contact, block) with f* < 1 that slide (the fstat's sliding flag,
    f_t at the Coulomb limit), share of those with f* >= 1 that slide, and share of the sliding samples
    that are weak;
  * contacts lost and recovered: share of the pairs that open (absent from a later block) and close
    again before tau = 1 (pair 1 of Fig. 3.10a opens at tau ~ 0.36 and closes at ~ 0.7);
  * sliding of strong contacts (ssl) and sticking of weak ones (wst) happen (the exceptions the thesis
    names);
and two pairs like the thesis' are drawn (Fig. 3.10): weak at tau = 0 and sliding at some tau <= 0.1, the
first also strong (f* > 1) at some time, the second also opening and closing again (chosen with a fixed
seed; without such a candidate, any weak-and-sliding pair).

Usage: chapter3-pairs.py OUT_DIR MU [MU ...]   (mu = 0 is left out: no friction to mobilise)
Writes OUT_DIR/ch3_pairs.csv (one row per mu), OUT_DIR/ch3_pair_muX_K.dat and, with gnuplot,
OUT_DIR/ch3_fig3_10.png (mu = 0.1 as in the thesis, or SNAP_MUS="MU"; else the first frictional mu). Reported, not gated: exit 0 unless no run could be
read (1) or the command line is wrong (2).
"""
import csv
import math
import os
import random
import sys

from ch3common import check_mus, cycle_rows, row_at_time, run_gnuplot, usage, write_table


def blocks(fstat, rows):
    """Yields (tau, [(i, j, fn, ft, sliding)]) for the blocks of the cycle, in file order."""
    cur, tau = None, None
    with open(fstat) as f:
        for line in f:
            if line.startswith("# time"):
                if cur is not None:
                    yield tau, cur
                k = row_at_time(float(line.split()[2]), rows)
                tau = rows[k][1] if k is not None else None
                cur = [] if tau is not None else None
            elif cur is not None and not line.startswith("#"):
                p = line.split()
                ft = math.sqrt(float(p[10]) ** 2 + float(p[11]) ** 2 + float(p[12]) ** 2)
                cur.append((int(p[0]), int(p[1]), float(p[9]), ft, p[16] != "0"))
    if cur is not None:
        yield tau, cur


def analyse(out, mu_s):
    mu = float(mu_s)
    rows = cycle_rows(f"{out}/UNI_mu{mu_s}.macro.csv")
    taus, track = [], {}
    n_weak = n_weak_sl = n_strong = n_strong_sl = 0
    for b, (tau, contacts) in enumerate(blocks(f"{out}/UNI_mu{mu_s}.fstat", rows)):
        taus.append(tau)
        loaded = [c for c in contacts if c[2] > 0]
        if not loaded:
            continue
        mean = sum(c[2] for c in loaded) / len(loaded)
        if b == 0:
            track = {(c[0], c[1]): [] for c in loaded}
        for i, j, fn, ft, sl in loaded:
            fstar = fn / mean
            if fstar < 1:
                n_weak += 1
                n_weak_sl += sl
            else:
                n_strong += 1
                n_strong_sl += sl
            seq = track.get((i, j))
            if seq is not None:
                seq.append((b, fstar, ft / (mu * fn), sl))
    if len(taus) < 5 or not track:
        raise ValueError("fewer than 5 blocks of the cycle, or no loaded contact at tau = 0")
    nb = len(taus)
    reopened = opened = 0
    for seq in track.values():
        present = [False] * nb
        for b, *_ in seq:
            present[b] = True
        first_gap = next((b for b in range(nb) if not present[b]), None)
        if first_gap is not None:
            opened += 1
            if any(present[first_gap:]):
                reopened += 1
    # Two pairs like the thesis' (both weak at the start and sliding early in the loading; after the
    # relaxation at constant volume hardly any contact slides at tau = 0, so "early" is tau <= 0.1): the
    # first also strong (f* > 1) at some time, the second also lost and found again; each chosen with a
    # fixed seed among the candidates, the plain weak-and-sliding ones when none has the extra property.
    def early(seq):
        return seq and seq[0][0] == 0 and seq[0][1] < 1 and any(sl for b, _, _, sl in seq if taus[b] <= 0.1)

    def reopens(seq):
        bs = [b for b, *_ in seq]
        return any(b2 > b1 + 1 for b1, b2 in zip(bs, bs[1:]))

    base = sorted(p for p, seq in track.items() if early(seq))
    rng = random.Random(2014)
    picks = []
    for extra in (lambda seq: any(x[1] > 1 for x in seq), reopens):
        cand = [p for p in base if extra(track[p]) and p not in picks] or [p for p in base if p not in picks]
        if cand:
            picks.append(rng.choice(cand))
    for k, p in enumerate(picks, 1):
        tmp = f"{out}/ch3_pair_mu{mu_s}_{k}.dat.tmp"
        with open(tmp, "w") as f:
            f.write(f"# pair {p[0]} {p[1]}: tau f* ft_over_mu_fn sliding (blank line: contact open)\n")
            last = -1
            for b, fstar, psi, sl in track[p]:
                if b != last + 1 and last >= 0:
                    f.write("\n")
                f.write(f"{taus[b]:.6g} {fstar:.6g} {psi:.6g} {int(sl)}\n")
                last = b
        os.replace(tmp, f"{out}/ch3_pair_mu{mu_s}_{k}.dat")
    res = {
        "pairs_at_tau0": len(track),
        "weak_samples_sliding": n_weak_sl / n_weak if n_weak else math.nan,
        "strong_samples_sliding": n_strong_sl / n_strong if n_strong else math.nan,
        "sliding_samples_weak": n_weak_sl / (n_weak_sl + n_strong_sl) if n_weak_sl + n_strong_sl else math.nan,
        "pairs_opened": opened / len(track),
        "pairs_opened_and_closed_again": reopened / len(track),
        "blocks": nb,
    }
    return res, picks


def plot(out, mu_s, picks):
    if not picks:
        return
    gp = ["set terminal pngcairo size 1200,450 noenhanced", f"set output '{out}/ch3_fig3_10.png'",
          f"set multiplot layout 1,{len(picks)}", "set xlabel 'tau'", "set xrange [0:1]", "set yrange [0:*]", "set offsets 0, 0, 0.08, 0",
          "set key below"]
    for k, p in enumerate(picks, 1):
        gp.append(f"set title 'mu = {mu_s}: pair {k} ({p[0]}, {p[1]})'")
        gp.append(f"plot '{out}/ch3_pair_mu{mu_s}_{k}.dat' u 1:3 w l t 'f_t/(mu f_n)', '' u 1:2 w l lw 2 t 'f* = f_n/<f_n>'")
    gp.append("unset multiplot")
    run_gnuplot(gp)


def main():
    if len(sys.argv) < 3:
        usage("usage: chapter3-pairs.py OUT_DIR MU [MU ...]")
    out, mus = sys.argv[1], sys.argv[2:]
    if not os.path.isdir(out):
        usage(f"chapter3-pairs.py: error: no directory {out}")
    check_mus("chapter3-pairs.py", mus)
    want = os.environ.get("SNAP_MUS", "0.1").split()
    res, drawn, first, requested = [], False, None, 0
    for mu in mus:
        if float(mu) <= 0:
            continue
        requested += 1
        if not os.path.exists(f"{out}/UNI_mu{mu}.fstat") or os.path.exists(f"{out}/UNI_mu{mu}.failed"):
            print(f"mu = {mu}: no UNI_mu{mu}.fstat (run with --fstat 1), left out")
            continue
        try:
            r, picks = analyse(out, mu)
        except (ValueError, KeyError, OSError, IndexError, TypeError, ZeroDivisionError, csv.Error) as e:
            print(f"mu = {mu}: cannot be analysed ({e}), left out")
            continue
        res.append((float(mu), mu, r))
        if first is None:
            first = (mu, picks)
        if not drawn and mu in want:
            plot(out, mu, picks)
            drawn = True
    if not drawn and first is not None:
        plot(out, *first)
    if not res:
        if requested == 0:
            print("chapter3-pairs.py: no frictional mu given; nothing to analyse")
            return 0
        print("chapter3-pairs.py: no run could be analysed")
        return 1
    print("\nContact pairs followed from tau = 0 (Fig. 3.10; weak: f* < 1, sliding: the fstat's flag)")
    write_table(f"{out}/ch3_pairs.csv", sorted(res))
    return 0


if __name__ == "__main__":
    sys.exit(main())
