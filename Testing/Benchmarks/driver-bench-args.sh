# Sourced (not run) by the driver-level benchmark scripts after setting bench_program:
# reads [BUILD_DIR] [THREADS] [OUT_DIR] from the caller's arguments, leaves the extra driver flags in
# "$@", changes to the repository root and sets build, threads, out and exe.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[1]}")/../.."
build="${1:-build}"
threads="${2:-2}"
out="${3:-$(mktemp -d)}"
shift $(( $# < 3 ? $# : 3 ))
exe="$build/bin/$bench_program"
[[ -x "$exe" ]] || { echo "$(basename "${BASH_SOURCE[1]}"): $exe not built" >&2; exit 1; }
mkdir -p "$out"
