# Shared by the explain-*.sh validation scripts: BIN (build/bin) and OUT (work folder) from $1 $2;
# SHARED: the shared data folder (default: ../shared next to the repository). Exit 77 = skipped.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
BIN="${1:-$HERE/../../build/bin}"
OUT="${2:-$HERE/../../build/Testing/explain-validation}"
SHARED="${PDPM_SHARED_DIR:-$HERE/../../../shared}"
mkdir -p "$OUT"
verdict() { python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print(r['verdict'], ', '.join(m['name'] for m in r['mechanisms']))" "$1"; }
