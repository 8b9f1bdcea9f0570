#!/usr/bin/env python3
"""Local crystalline order and contact directions of a packing, read from a PowderDPM restart file.

Why: thesis Sec. 3.5 / Appendix II find a contact distribution P(theta) with "two strong peaks at
about pi/2 +- pi/4 and a local maximum at pi/2", which our packings do not show
(Documentation/validation-thesis-ch3.md, "P(theta)'s peaks and local crystalline order"). Those three directions are exactly the
nearest-neighbour directions of a face-centred cubic lattice aligned with the box axes (<110>:
8 of 12 neighbours at 45 / 135 degrees to z, 4 at 90 degrees). This script measures how much of a
packing is locally crystalline and what P(theta) its contacts have, so the two can be compared.

For each restart file it prints one line:
  N, v (volume fraction of the spheres, overlaps ignored), contacts per particle,
  crystalline fraction: particles with at least 7 of their 12 nearest neighbours (distance scaled
    by r_i + r_j) "solid-like" bonds, d6(i, j) > 0.7 (ten Wolde-Ruiz-Montero-Frenkel bond order with
    l = 6; d6 = q6(i).q6*(j) / |q6(i)||q6(j)|, computed through the addition theorem as sums of
    Legendre P6 of neighbour-direction dot products, so no complex harmonics are needed),
  P(theta) of the contacts (overlap > 0) in nine 10-degree bins of theta folded into [0, 90] deg,
    normalised so that an isotropic distribution gives 1 in every bin: phi/(cos theta_i - cos theta_f),
    twice pdpm-polar's P(theta) = phi/(2 dtheta sin theta), whose isotropic value is 1/2.
A particle needs 12 neighbours in its 27 cells for the bond order; a file with fewer particles, or an
isolated particle, is refused.
--fcc N reads no file and checks the measure on a perfect box-aligned FCC crystal of 4 N^3 spheres
instead (crystalline fraction 1, P(theta) only in the 40-50 and 80-90 degree bins).

Usage: packing-order.py RUN.restart [RUN.restart ...] | packing-order.py --fcc 6
Bad input (missing file, not a PowderDPM restart, truncated particle section): one line, exit 2.
"""
import math
import sys


def fail(message):
    print(f"packing-order.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_restart(path):
    """Box lengths, periodic flags and (x, y, z, r) of every particle."""
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    except UnicodeDecodeError:
        fail(f"{path}: not a PowderDPM restart file (not text)")
    if not lines or not lines[0].startswith("PowderDPM-restart"):
        fail(f"{path}: not a PowderDPM restart file (first line '{lines[0][:40] if lines else ''}')")
    box = None
    walls_seen = False  # "particles N" also names a driver parameter; the section follows "walls"
    for k, line in enumerate(lines):
        w = line.split()
        if not w:
            continue
        if w[0] == "box" and len(w) >= 10:
            try:
                lo = [float(v) for v in w[1:4]]
                hi = [float(v) for v in w[4:7]]
            except ValueError:
                fail(f"{path}: malformed box line '{line[:60]}'")
            box = ([h - l for l, h in zip(lo, hi)], [w[7 + i] == "1" for i in range(3)])
            if not all(math.isfinite(x) and x > 0 for x in box[0]):
                fail(f"{path}: box lengths must be finite and positive")
        if w[0] == "walls":
            walls_seen = True
        if w[0] == "particles" and len(w) == 2 and walls_seen:
            if box is None:
                fail(f"{path}: no box line before the particle section")
            try:
                n = int(w[1])
            except ValueError:
                fail(f"{path}: malformed particle count '{w[1]}'")
            if n < 13:
                fail(f"{path}: {n} particles; the bond order needs at least 13")
            if k + n >= len(lines):
                fail(f"{path}: truncated particle section ({n} particles announced)")
            parts = []
            for line2 in lines[k + 1:k + 1 + n]:
                v = line2.split()
                try:
                    if len(v) < 16:
                        raise ValueError
                    parts.append((float(v[0]), float(v[1]), float(v[2]), float(v[15])))
                except ValueError:
                    fail(f"{path}: malformed particle line '{line2[:60]}'")
                if not all(math.isfinite(c) for c in parts[-1]) or parts[-1][3] <= 0:
                    fail(f"{path}: particle {len(parts) - 1} has a non-finite position or a radius <= 0")
            return box, parts
    fail(f"{path}: no particle section")


def fcc(cells):
    a = 1.0
    base = [(0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5)]
    r = a / (2 * math.sqrt(2)) * 1.001  # touching spheres, a hair of overlap so contacts count
    parts = [((i + bx) * a, (j + by) * a, (k + bz) * a, r)
             for i in range(cells) for j in range(cells) for k in range(cells) for bx, by, bz in base]
    return ([cells * a] * 3, [True] * 3), parts


def p6(c):
    c2 = c * c
    return (231 * c2 * c2 * c2 - 315 * c2 * c2 + 105 * c2 - 5) / 16


def analyse(box, parts):
    L, per = box
    n = len(parts)
    rmax = max(p[3] for p in parts)
    cut = 2 * rmax * 1.6  # 12 nearest (scaled) neighbours lie well inside
    nc = [max(1, int(L[a] // cut)) for a in range(3)]
    cells = {}
    for i, p in enumerate(parts):
        key = tuple(int((p[a] % L[a]) / L[a] * nc[a]) % nc[a] if per[a] else
                    min(nc[a] - 1, max(0, int(p[a] / L[a] * nc[a]))) for a in range(3))
        cells.setdefault(key, []).append(i)

    def sep(i, j):
        d = [parts[j][a] - parts[i][a] for a in range(3)]
        for a in range(3):
            if per[a]:
                d[a] -= L[a] * round(d[a] / L[a])
        return d

    neigh = []      # 12 nearest by d / (r_i + r_j): unit vectors and indices
    contacts = []   # unit normals of touching pairs, each pair once
    for i, p in enumerate(parts):
        key = tuple(int((p[a] % L[a]) / L[a] * nc[a]) % nc[a] if per[a] else
                    min(nc[a] - 1, max(0, int(p[a] / L[a] * nc[a]))) for a in range(3))
        cand = []
        seen = set()
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    k2 = ((key[0] + dx) % nc[0], (key[1] + dy) % nc[1], (key[2] + dz) % nc[2])
                    if k2 in seen:
                        continue
                    seen.add(k2)
                    for j in cells.get(k2, ()):
                        if j == i:
                            continue
                        d = sep(i, j)
                        dist = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
                        if dist == 0:
                            continue
                        u = (d[0] / dist, d[1] / dist, d[2] / dist)
                        cand.append((dist / (p[3] + parts[j][3]), j, u))
                        if j > i and dist < p[3] + parts[j][3]:
                            contacts.append(u)
        cand.sort()
        if len(cand) < 12:
            fail(f"particle {i} has {len(cand)} neighbours within {cut:.3g} (12 needed): too sparse a packing")
        neigh.append([(j, u) for _, j, u in cand[:12]])
    # q6 norms through the addition theorem: |q6(i)|^2 ~ (1/N_i^2) sum_ab P6(u_a . u_b)
    norm = []
    for nb in neigh:
        s = 0.0
        for _, ua in nb:
            for _, ub in nb:
                s += p6(ua[0] * ub[0] + ua[1] * ub[1] + ua[2] * ub[2])
        norm.append(math.sqrt(max(s, 1e-300)) / len(nb))
    crystalline = 0
    for i, nb in enumerate(neigh):
        solid = 0
        for j, _ in nb:
            s = 0.0
            for _, ua in nb:
                for _, ub in neigh[j]:
                    s += p6(ua[0] * ub[0] + ua[1] * ub[1] + ua[2] * ub[2])
            d6 = s / (len(nb) * len(neigh[j])) / (norm[i] * norm[j])
            if d6 > 0.7:
                solid += 1
        if solid >= 7:
            crystalline += 1
    bins = [0] * 9
    for u in contacts:
        th = math.degrees(math.acos(min(1.0, abs(u[2]))))
        bins[min(8, int(th // 10))] += 1
    P = []
    for b in range(9):
        share = math.cos(math.radians(10 * b)) - math.cos(math.radians(10 * (b + 1)))
        P.append(bins[b] / max(1, len(contacts)) / share)
    vol = L[0] * L[1] * L[2]
    v = sum(4 / 3 * math.pi * p[3] ** 3 for p in parts) / vol
    return n, v, 2 * len(contacts) / n, crystalline / n, P


def main():
    args = sys.argv[1:]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        sys.exit(0 if args else 2)
    runs = []
    if args[0] == "--fcc":
        if len(args) != 2 or not args[1].isdigit() or not 2 <= int(args[1]) <= 20:
            fail("--fcc takes one whole number of unit cells per side, 2 ... 20")
        runs.append((f"fcc {args[1]}^3 cells", *fcc(int(args[1]))))
    else:
        for path in args:
            if path.startswith("--"):
                fail(f"unknown flag {path}")
            runs.append((path, *read_restart(path)))
    results = [(name, *analyse(box, parts)) for name, box, parts in runs]  # every file checked before output
    print("file,N,volume_fraction,contacts_per_particle,crystalline_fraction," +
          ",".join(f"P_{10 * b}_{10 * b + 10}deg" for b in range(9)))
    for name, n, v, c, x, P in results:
        print(f"{name},{n},{v:.4f},{c:.3f},{x:.4f}," + ",".join(f"{p:.3f}" for p in P))


if __name__ == "__main__":
    main()
