"""Helpers shared by the chapter-3 analysis scripts (chapter3-eigen.py, chapter3-mobilisation.py,
chapter3-polar.py, chapter3-pairs.py)."""
import csv
import os
import shutil
import subprocess
import sys


def finite(values):
    return [x for x in values if x == x]


def extreme(rows, k, pick):
    """(value, tau) of the largest (pick=max) or smallest (pick=min) finite column k of rows whose
    column 0 is tau; (NaN, NaN) if there is none."""
    best = None
    for x in rows:
        if x[k] == x[k] and (best is None or pick(x[k], best[k]) != best[k]):
            best = x
    return (best[k], best[0]) if best is not None else (float("nan"), float("nan"))


def write_table(path, res):
    """res: [(mu as float, mu as given, {quantity: value})], sorted by mu. Writes PATH (one row per mu,
    written to a temporary name and renamed) and prints the quantities as rows, one column per mu."""
    keys = list(res[0][2].keys())
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("mu," + ",".join(keys) + "\n")
        for m, _, a in res:
            f.write(f"{m:g}," + ",".join(f"{a[k]:.6g}" for k in keys) + "\n")
    os.replace(tmp, path)
    w = max(len(k) for k in keys)
    print(f"{'quantity':<{w}} " + " ".join(f"{'mu=' + s:>9}" for _, s, _ in res))
    for k in keys:
        print(f"{k:<{w}} " + " ".join(f"{a[k]:9.4g}" for _, _, a in res))


def analyse_runs(out_dir, mus, plot_prefix, analyse_one, what, skip=lambda mu: False):
    """Runs analyse_one(macro_csv_path, plot_path) -> {quantity: value} (it also writes plot_path) for
    every mu of MUS that is not skipped, with OUT_DIR/UNI_muX.macro.csv present and no .failed marker.
    A plot file of an earlier analysis is removed first, so a run left out this time is not drawn.
    Returns [(mu as float, mu as given, result)] sorted by mu; an empty list when nothing was to be
    analysed (every mu skipped, or only files of an older driver without the columns); exits with
    status 1 when no requested run could be read."""
    res = []
    wanted = old_files = 0
    for mu in mus:
        path = f"{out_dir}/UNI_mu{mu}.macro.csv"
        plot = f"{out_dir}/{plot_prefix}{mu}.dat"
        if os.path.exists(plot):
            os.remove(plot)
        if skip(mu):
            continue
        wanted += 1
        if not os.path.exists(path) or os.path.exists(f"{out_dir}/UNI_mu{mu}.failed"):
            print(f"mu = {mu}: no run, left out")
            continue
        try:
            res.append((float(mu), mu, analyse_one(path, plot)))
        except KeyError as e:
            print(f"mu = {mu}: {path} has no column {e} (written by an older driver), left out")
            old_files += 1
        except TypeError:  # csv gives None for the fields missing from a short row
            print(f"mu = {mu}: {path} has a row with missing fields (truncated file?), left out")
        except (ValueError, ZeroDivisionError) as e:
            print(f"mu = {mu}: {path} cannot be analysed ({e}), left out")
    if not res:
        if wanted == 0 or old_files:
            print(f"{what}: " + ("no run requested" if wanted == 0 else "only files without its columns") + "; not analysed")
            return []
        raise SystemExit(f"{what}: no run could be read")
    return sorted(res)


def usage(text):
    """A wrong command line: one line on stderr, exit code 2 (the project's rule for bad input)."""
    print(text, file=sys.stderr)
    raise SystemExit(2)


def check_mus(script, mus):
    """Every MU argument must be a number: otherwise one line on stderr, exit code 2."""
    for mu in mus:
        try:
            float(mu)
        except ValueError:
            usage(f"{script}: error: '{mu}' is not a friction coefficient")


def cycle_rows(path):
    """[(time, tau, eps_dev)] of the rows of RUN.macro.csv with tau in [0, 1] (the cycle; the
    preparation's rows have tau < 0); ValueError if there are fewer than 5."""
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            tau = float(r["tau"])
            if -1e-9 <= tau <= 1 + 1e-9:
                rows.append((float(r["time"]), tau, float(r["eps_dev"])))
    if len(rows) < 5:
        raise ValueError("fewer than 5 rows of the cycle")
    return rows


def row_at_time(t, rows):
    """Index of the row of cycle_rows() written at time t (the same output step), or None."""
    for k, (tr, _, _) in enumerate(rows):
        if abs(tr - t) <= 1e-9 * max(1.0, abs(tr)) + 1e-15:
            return k
    return None


def run_gnuplot(lines):
    """Runs gnuplot on the script lines if gnuplot is installed; a failure is reported, not raised."""
    if not shutil.which("gnuplot"):
        print("gnuplot not found: no plots")
        return
    r = subprocess.run(["gnuplot"], input="\n".join(lines) + "\n", capture_output=True, text=True)
    if r.returncode != 0:
        print("gnuplot failed: " + r.stderr.strip()[-300:])
