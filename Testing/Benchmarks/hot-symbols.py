#!/usr/bin/env python3
"""Lists the functions a benchmark run executes, for the linker's symbol ordering file.

Usage: hot-symbols.py BINARY CALLGRIND_OUT [CALLGRIND_OUT ...] > hot-symbols.txt
       hot-symbols.py --check BINARY hot-symbols.txt

--check (a fast test): fails when the list has gone stale for BINARY, i.e. when fewer than 90 % of
the listed functions that come from the kernel (names with "pdpm") exist in BINARY, or when none of
the names under which a step-loop function (STEP_LOOP below) exists in BINARY is listed. A stale
list costs memory, never results; the message says how to regenerate it.

Each CALLGRIND_OUT is a `valgrind --tool=callgrind --dump-instr=yes` profile of BINARY. Every
function (text symbol of BINARY, mangled) with at least one executed instruction is printed once,
most instructions first. Valgrind's virtual CPU has no AVX-512, so glibc's string functions pick
their AVX2 variants under it; where a variant like __memmove_avx_unaligned_erms ran, all variants
of that function (__memmove_*) are listed too, so that the one the real CPU picks is grouped with
the rest. Why: see Documentation/performance.md ("Program text").
"""
import bisect
import collections
import re
import subprocess
import sys


def text_symbols(binary):
    out = subprocess.run(["nm", "-S", "--defined-only", binary], capture_output=True, text=True,
                         check=True).stdout
    syms = []
    for line in out.splitlines():
        p = line.split(None, 3)
        if len(p) == 4 and p[2] in "tTwWiI":
            syms.append((int(p[0], 16), int(p[1], 16), p[3]))
    syms.sort()
    return syms


def executed(profile, syms, starts, cost):
    """Adds the instructions of each cost line (position columns: instr line) to its function."""
    last = 0
    with open(profile, errors="replace") as f:
        for line in f:
            if not line or line[0] not in "0123456789+-*":
                continue
            tok = line.split()
            a = tok[0]
            if a.startswith("0x"):
                addr = int(a, 16)
            elif a[0] == "+":
                addr = last + int(a[1:])
            elif a[0] == "-":
                addr = last - int(a[1:])
            elif a == "*":
                addr = last
            else:
                continue
            last = addr
            i = bisect.bisect_right(starts, addr) - 1
            if i >= 0 and syms[i][0] <= addr < syms[i][0] + max(syms[i][1], 1):
                n = int(tok[2]) if len(tok) > 2 and tok[2].isdigit() else 1
                cost[syms[i][2]] += n


# Functions every step of both decks runs: (substring of the mangled name).
STEP_LOOP = ["DPMBase18integrateFirstHalf", "DPMBase19integrateSecondHalf", "DPMBase13computeForces",
             "NeighbourList5build", "LinearBatch8evaluate"]


def check(binary, listing):
    with open(listing) as f:
        listed = [l.strip() for l in f if l.strip()]
    have = {s[2] for s in text_symbols(binary)}
    ours = [n for n in listed if "pdpm" in n]
    found = sum(1 for n in ours if n in have)
    problems = []
    if not ours or found < 0.9 * len(ours):
        problems.append(f"only {found} of the {len(ours)} kernel functions it lists exist in {binary}")
    listed_set = set(listed)
    for key in STEP_LOOP:
        names = sorted(n for n in have if key in n and ".cold" not in n)  # cold parts never run
        if not names:
            problems.append(f"no function named like {key} in {binary} (update STEP_LOOP in hot-symbols.py)")
        if names and not any(n in listed_set for n in names):  # template variants may not all run
            problems.append(f"none of {', '.join(names)} is listed")
    if problems:
        sys.stderr.write(f"hot-symbols.py: {listing} is stale: {problems[0]}"
                         f"{f' (and {len(problems) - 1} more)' if len(problems) > 1 else ''}; "
                         "regenerate it with Testing/Benchmarks/make-hot-symbols.sh\n")
        return 1
    print(f"hot-symbols.py: {found}/{len(ours)} listed kernel functions present, step loop listed")
    return 0


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--check":
        return check(sys.argv[2], sys.argv[3])
    if len(sys.argv) < 3:
        sys.stderr.write("usage: hot-symbols.py BINARY CALLGRIND_OUT [...]\n")
        return 2
    syms = text_symbols(sys.argv[1])
    starts = [s[0] for s in syms]
    cost = collections.Counter()
    for prof in sys.argv[2:]:
        executed(prof, syms, starts, cost)
    names = [n for n, _ in sorted(cost.items(), key=lambda kv: (-kv[1], kv[0]))]
    variant = re.compile(r"^(__[a-z0-9]+)_(sse2|sse4_1|sse4_2|sse42|ssse3|avx2|avx|evex|avx512)")
    allnames = sorted({s[2] for s in syms})
    seen = set(names)
    extra = []
    for n in names:
        m = variant.match(n)
        if m:
            for o in allnames:
                if o.startswith(m.group(1) + "_") and o not in seen:
                    seen.add(o)
                    extra.append(o)
    for n in names + extra:
        print(n)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (OSError, subprocess.CalledProcessError, ValueError) as e:
        sys.stderr.write(f"hot-symbols.py: {e}\n")
        sys.exit(2)
