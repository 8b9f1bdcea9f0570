#!/usr/bin/env bash
# Bad input to pdpm-cg / pdpm-polar must give exactly one line "PROGRAM: error: …" on stderr and
# exit code 2. Usage: ToolsBadInput.sh PDPM_CG PDPM_POLAR
set -u
CG=$1
POLAR=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail=0
printf '# time 0 step 0 contacts 2\n# box 0 1 0 1 0 1 periodic 0 0 0\n0 1 0 0 0 0.1 0 0 1\n' > "$work/bad.fstat"
printf 'not xml at all\n' > "$work/bad.vtu"
printf '# time 0 step 0 contacts 1\n# box 0 1 0 1 0 1 periodic 0 0 0\n0 1 0.5 0.5 0.5 0.01 0 0 1 1 0 0 0 0 0 0.1 0\n' > "$work/good.fstat"
expect2() {  # description, command…
    local what=$1; shift
    "$@" >"$work/out" 2>"$work/err"
    local rc=$?
    local lines
    lines=$(wc -l <"$work/err")
    if [ "$rc" -ne 2 ] || [ "$lines" -ne 1 ] || ! grep -q '^pdpm-[a-z]*: error: ' "$work/err"; then
        echo "FAIL: $what: exit $rc, stderr:"; cat "$work/err"; fail=1
    else
        echo "ok: $what: $(cat "$work/err")"
    fi
}
expect2 "cg missing file"      "$CG" --input "$work/missing.vtu" --nz 10 --output "$work/o"
expect2 "cg malformed vtu"     "$CG" --input "$work/bad.vtu" --nz 10 --output "$work/o"
expect2 "cg malformed fstat"   "$CG" --input "$work/bad.fstat" --nz 10 --output "$work/o"
expect2 "cg width zero"        "$CG" --input "$work/good.fstat" --nz 10 --width 0
expect2 "cg width negative"    "$CG" --input "$work/good.fstat" --nz 10 --width -1
expect2 "cg empty grid"        "$CG" --input "$work/good.fstat" --width 1
expect2 "cg no input"          "$CG" --nz 10
expect2 "cg unknown flag"      "$CG" --input "$work/good.fstat" --nz 10 --bogus 1
expect2 "cg bad kernel"        "$CG" --input "$work/good.fstat" --nz 10 --kernel box
expect2 "cg contacts only"     "$CG" --input "$work/good.fstat" --nz 10 --output "$work/o"
expect2 "polar missing file"   "$POLAR" --input "$work/missing.fstat" --plot none
expect2 "polar malformed"      "$POLAR" --input "$work/bad.fstat" --plot none
expect2 "polar wrong type"     "$POLAR" --input "$work/bad.vtu" --plot none
expect2 "polar bad chi"        "$POLAR" --input "$work/good.fstat" --chi 1.5
expect2 "polar zero axis"      "$POLAR" --input "$work/good.fstat" --axis 0,0,0 --plot none
expect2 "polar layers oblique" "$POLAR" --input "$work/good.fstat" --layers 3 --axis 1,0,0 --plot none --output "$work/lay"
expect2 "polar layers negative" "$POLAR" --input "$work/good.fstat" --layers -1 --plot none --output "$work/lay"
printf '# time 0 step 0 contacts 1\n# box 0 1 0 1 0 0 periodic 0 0 0\n0 1 0.5 0.5 0.5 0.01 0 0 1 1 0 0 0 0 0 0.1 0\n' > "$work/flat.fstat"
expect2 "polar layers flat box" "$POLAR" --input "$work/flat.fstat" --layers 3 --plot none --output "$work/lay"
[ -e "$work/lay" ] && { echo "FAIL: refused --layers runs left $work/lay behind"; fail=1; }
"$CG" --help >/dev/null || { echo "FAIL: cg --help"; fail=1; }
"$POLAR" --help >/dev/null || { echo "FAIL: polar --help"; fail=1; }
exit $fail
