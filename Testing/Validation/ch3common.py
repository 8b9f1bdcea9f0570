"""Helpers shared by the chapter-3 analysis scripts (chapter3-eigen.py, chapter3-mobilisation.py)."""
import os


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
