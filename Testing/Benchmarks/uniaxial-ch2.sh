#!/usr/bin/env bash
# Times the full-scale thesis-ch2 uniaxial cycle (issue target: under 30 minutes on 2 cores):
# UniaxialCyclic --preset thesis-ch2 (N = 9261, frictionless, T = 5000 us at dt = t_c/50, about 1e10
# particle-steps), which first runs its own isotropic preparation to v0 = 0.64. Prints the wall time
# of the preparation and of the cycle (stage 'load' to the end) and the cycle's particle-steps per
# second. Needs a quiet machine (Documentation/performance.md).
#   Testing/Benchmarks/uniaxial-ch2.sh [BUILD_DIR] [THREADS] [OUT_DIR] [extra driver flags...]
bench_program=UniaxialCyclic
source "$(dirname "$0")/driver-bench-args.sh"
python3 - "$exe" "$threads" "$out" "$@" <<'PY'
import re, subprocess, sys, time
exe, threads, out, extra = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
cmd = [exe, "--preset", "thesis-ch2", "--threads", threads, "--output", out, "--name", "uni_ch2", "--vtk", "0",
       "--save_fractions", ""] + extra
t0 = time.time()
p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
buf, last, t_load, log = b"", "", None, open(f"{out}/uni_ch2.stderr", "w")
while True:
    c = p.stderr.read1(4096)
    if not c:
        break
    buf += c
    parts = re.split(rb"[\r\n]", buf)
    buf = parts.pop()
    for line in parts:
        s = line.decode(errors="replace").strip()
        if not s:
            continue
        if "stage 'load'" in s and t_load is None:
            t_load = time.time()
        if "stage '" in s:
            log.write(f"{time.time() - t0:9.1f} s  {s}\n")
            log.flush()
        last = s
rc = p.wait()
t1 = time.time()
if rc != 0 or t_load is None:
    sys.exit(f"uniaxial-ch2.sh: run failed (exit {rc}); see {out}/uni_ch2.stderr")
# steps of the cycle: period / dt, and the particle count, from the restart file
period = dt = n = None
for line in open(f"{out}/uni_ch2.restart"):
    w = line.split()
    if w[:1] == ["time"]:
        dt = float(w[5])
    elif w[:1] == ["period"] and period is None:
        period = float(w[1])
    elif w[:1] == ["particles"] and n is None:
        n = int(w[1])
cycle_steps = period / dt
print(f"uniaxial_ch2 threads={threads} wall_s={t1 - t0:.1f} prep_s={t_load - t0:.1f} cycle_s={t1 - t_load:.1f} "
      f"cycle_steps={cycle_steps:.0f} dt_s={dt:.4g} cycle_particle_steps_per_s={n * cycle_steps / (t1 - t_load):.3g}")
print(f"last progress line: {last}")
PY
echo "output in $out"
