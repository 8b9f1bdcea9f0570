#!/usr/bin/env bash
# Bad input to pdpm-cg / pdpm-polar / pdpm-tools-example / pdpm-cg-benchmark / pdpm-fit must give
# exactly one line "PROGRAM: error: …" on stderr and exit code 2, and leave no *.tmp file behind.
# Usage: ToolsBadInput.sh PDPM_CG PDPM_POLAR PDPM_TOOLS_EXAMPLE PDPM_CG_BENCHMARK PDPM_FIT
set -u
CG=$(realpath "$1"); POLAR=$(realpath "$2"); EXAMPLE=$(realpath "$3"); BENCH=$(realpath "$4"); FIT=$(realpath "$5")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"  # a probe that is wrongly accepted writes here, not into the caller's directory
fail=0
printf '# time 0 step 0 contacts 2\n# box 0 1 0 1 0 1 periodic 0 0 0\n0 1 0 0 0 0.1 0 0 1\n' > "$work/bad.fstat"
printf 'not xml at all\n' > "$work/bad.vtu"
printf '# time 0 step 0 contacts 1\n# box 0 1 0 1 0 1 periodic 0 0 0\n0 1 0.5 0.5 0.5 0.01 0 0 1 1 0 0 0 0 0 0.1 0\n' > "$work/good.fstat"
"$EXAMPLE" --output "$work/ex" >/dev/null || { echo "FAIL: pdpm-tools-example"; fail=1; }
vtu="$work/ex/column_0000.vtu"  # a good particle file: probes that must fail for one reason only
expect2() {  # description, command…
    local what=$1; shift
    "$@" >"$work/out" 2>"$work/err"
    local rc=$?
    local lines
    lines=$(wc -l <"$work/err")
    if [ "$rc" -ne 2 ] || [ "$lines" -ne 1 ] || ! grep -q '^pdpm-[a-z-]*: error: ' "$work/err"; then
        echo "FAIL: $what: exit $rc, stderr:"; cat "$work/err"; fail=1
    else
        echo "ok: $what: $(cat "$work/err")"
    fi
    local tmps
    tmps=$(find "$work" -name '*.tmp')
    [ -z "$tmps" ] || { echo "FAIL: $what: left $tmps behind"; fail=1; rm -rf $tmps; }
}
says() {  # description, pattern: the last refusal's message matches the pattern (grep -E)
    grep -Eq -- "$2" "$work/err" || { echo "FAIL: $1: message does not match '$2'"; fail=1; }
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
# bad numbers in list flags: named once (--region, not ----region), finite, non-zero axis
expect2 "cg region not a number" "$CG" --input "$work/good.fstat" --nz 10 --region a,1,0,1,0,1
says "cg region not a number" '^pdpm-cg: error: --region: '
expect2 "cg centre not a number" "$CG" --input "$work/good.fstat" --nz 10 --cylindrical 1 --centre a,0
says "cg centre not a number" '^pdpm-cg: error: --centre: '
expect2 "polar axis not a number" "$POLAR" --input "$work/good.fstat" --plot none --axis a,0,1
says "polar axis not a number" '^pdpm-polar: error: --axis: '
expect2 "cg region inf"        "$CG" --input "$vtu" --nz 10 --region 0,1,0,1,0,inf
expect2 "cg centre nan"        "$CG" --input "$vtu" --nz 10 --cylindrical 1 --centre nan,0
expect2 "cg width inf"         "$CG" --input "$vtu" --nz 10 --width inf
says "cg width inf" 'finite'
expect2 "polar axis inf"       "$POLAR" --input "$work/good.fstat" --plot none --axis inf,0,0 --output "$work/p"
expect2 "polar axis overflow"  "$POLAR" --input "$work/good.fstat" --plot none --axis 1e200,0,0 --output "$work/p"
expect2 "polar pdf_max inf"    "$POLAR" --input "$work/good.fstat" --plot none --pdf_max inf --output "$work/p"
expect2 "polar mu inf"         "$POLAR" --input "$work/good.fstat" --plot none --mu inf --output "$work/p"
expect2 "polar mu nan"         "$POLAR" --input "$work/good.fstat" --plot none --mu nan --output "$work/p"
[ -e "$work/p" ] && { echo "FAIL: refused polar runs left $work/p behind"; fail=1; }
# empty output names
expect2 "cg empty name"        "$CG" --input "$vtu" --nz 10 --name ''
expect2 "cg empty output"      "$CG" --input "$vtu" --nz 10 --output ''
expect2 "polar empty name"     "$POLAR" --input "$work/good.fstat" --plot none --name ''
expect2 "polar empty output"   "$POLAR" --input "$work/good.fstat" --plot none --output ''
expect2 "example empty output" "$EXAMPLE" --output ''
printf '# time 0 step 0 contacts 1000000000000000000\n# box 0 1 0 1 0 1 periodic 0 0 0\n' > "$work/hugecount.fstat"
expect2 "polar huge contact count" "$POLAR" --input "$work/hugecount.fstat" --plot none --output "$work/p"
# a run whose blocks all lack contacts: the error line only, no note before it
printf '# time 0 step 0 contacts 0\n# box 0 1 0 1 0 1 periodic 0 0 0\n' > "$work/nocontacts.fstat"
expect2 "polar no contacts"    "$POLAR" --input "$work/nocontacts.fstat" --plot none --output "$work/p"
printf '# time 0 step 0 contacts 1\n# box 0 1 0 1 0 1 periodic 2 0 0\n0 1 0.5 0.5 0.5 0.01 0 0 1 1 0 0 0 0 0 0.1 0\n' > "$work/periodic2.fstat"
expect2 "polar periodic flag 2" "$POLAR" --input "$work/periodic2.fstat" --plot none --output "$work/p"
printf '# time 0 step 0 contacts 1\n# box 0 1 0 1 0 1 periodic 0 0 0\n0 1 0.5 0.5 0.5 0.01 3 4 0 1 0 0 0 0 0 0.1 0\n' > "$work/scaled.fstat"
expect2 "polar normal not a unit vector" "$POLAR" --input "$work/scaled.fstat" --plot none --output "$work/p"
says "polar normal not a unit vector" 'not a unit vector'
printf '# time 0 step 0 contacts 1\n# box 0 1 0 1 0 1 periodic 0 0 0\n0 1 0.5 0.5 0.5 0.01 0 0 1 1e308 0 0 0 0 0 0.1 0\n' > "$work/hugef.fstat"
expect2 "polar force 1e308"    "$POLAR" --input "$work/hugef.fstat" --plot none --output "$work/p"
printf 'tau,p_nd,eps_dev\n0.1,1,0\n0.2,1,0.01\n' > "$work/short.macro.csv"
expect2 "fit steady too short" "$FIT" steady "$work/short.macro.csv"
printf 'tau,p_nd,volume_fraction,C_star\n0.1,1,0.6,6\n0.2,1,-0.6,6\n' > "$work/negv.macro.csv"
expect2 "fit volume fraction negative" "$FIT" cstar "$work/negv.macro.csv"
says "fit volume fraction negative" 'volume_fraction .* outside \(0, 1\)'
# pdpm-cg-benchmark: arguments checked, --help
expect2 "bench negative N"     "$BENCH" -5
expect2 "bench zero grid"      "$BENCH" 100 0 1
expect2 "bench not a number"   "$BENCH" 100 x 1
expect2 "bench too many"       "$BENCH" 100 10 1 5
"$BENCH" --help >/dev/null || { echo "FAIL: bench --help"; fail=1; }
# particle files with impossible sizes in the XML header
LC_ALL=C sed -e '0,/NumberOfTuples="1"/s//NumberOfTuples="-1"/' "$vtu" > "$work/neg_tuples.vtu"
LC_ALL=C sed -e 's/NumberOfPoints="[0-9]*"/NumberOfPoints="2000000000"/' "$vtu" > "$work/big_points.vtu"
LC_ALL=C sed -e 's/NumberOfCells="[0-9]*"/NumberOfCells="x"/' "$vtu" > "$work/bad_cells.vtu"
expect2 "cg vtu negative tuples" "$CG" --input "$work/neg_tuples.vtu" --nz 5 --output "$work/o"
expect2 "cg vtu huge points"   "$CG" --input "$work/big_points.vtu" --nz 5 --output "$work/o"
expect2 "cg vtu bad cells"     "$CG" --input "$work/bad_cells.vtu" --nz 5 --output "$work/o"
# grids too large for memory: refused by size, and std::bad_alloc is an error line too
expect2 "cg huge grid"         "$CG" --input "$vtu" --nx 100000 --ny 100000 --nz 100000 --output "$work/o"
says "cg huge grid" '--nx'
if grep -qa __asan_init "$CG"; then  # AddressSanitizer reserves far more address space than the limit
    echo "skipped: cg out of memory (sanitizer build)"
else
    expect2 "cg out of memory" bash -c 'ulimit -v 800000; exec "$@"' cg "$CG" --input "$vtu" --nx 200 --ny 200 --nz 200 --threads 1 --format csv --output "$work/o"
    says "cg out of memory" 'out of memory'
fi
# a collection whose timestep is not a number, a particle file without its time field
sed 's/timestep="0"/timestep="nan"/' "$work/ex/column.pvd" > "$work/ex/nan.pvd"
expect2 "cg pvd timestep nan"  "$CG" --input "$work/ex/nan.pvd" --nz 5 --output "$work/o"
says "cg pvd timestep nan" 'timestep "nan" is not a finite number'
# a collection cut short, or one listing a data set without its file: refused, not read in part
head -n 4 "$work/ex/column.pvd" > "$work/ex/cut.pvd"
expect2 "cg pvd cut short"     "$CG" --input "$work/ex/cut.pvd" --nz 5 --output "$work/o"
says "cg pvd cut short" 'truncated collection'
sed '0,/ file="[^"]*"/s// file=""/' "$work/ex/column.pvd" > "$work/ex/nofile.pvd"
expect2 "cg pvd data set without file" "$CG" --input "$work/ex/nofile.pvd" --nz 5 --output "$work/o"
says "cg pvd data set without file" 'without a file attribute'
LC_ALL=C sed 's/Name="time"/Name="tyme"/' "$vtu" > "$work/ex/notime.vtu"
expect2 "cg vtu without time"  "$CG" --input "$work/ex/notime.vtu" --nz 5 --output "$work/o"
says "cg vtu without time" "field data 'time' missing \\(not a PowderDPM particle file"
# outputs that cannot be written: refused, no .tmp left behind
mkdir -p "$work/od/cg.csv" "$work/ov/cg.vti" "$work/ob/polar_bins.csv" "$work/os/polar_series.csv" "$work/oe/column.pvd"
expect2 "cg csv blocked"       "$CG" --input "$vtu" --nz 5 --output "$work/od"
expect2 "cg vti blocked"       "$CG" --input "$vtu" --nz 5 --output "$work/ov" --format vti
# output names that would leave the output directory or end a quoted name in a gnuplot script
expect2 "cg name with a slash" "$CG" --input "$vtu" --nz 5 --output "$work/ov" --name a/b --format vti
says "cg name with a slash" 'not a plain file name'
expect2 "cg name escapes"      "$CG" --input "$vtu" --nz 5 --output "$work/ov/x/y" --name ../../escape
[ -e "$work/ov/escape.csv" ] && { echo "FAIL: cg --name ../../escape wrote outside --output"; fail=1; }
expect2 "cg name dot-dot"      "$CG" --input "$vtu" --nz 5 --output "$work/ov" --name ..
expect2 "polar name quote"     "$POLAR" --input "$work/good.fstat" --plot none --output "$work/p" --name "a'b"
expect2 "polar bins blocked"   "$POLAR" --input "$work/good.fstat" --plot none --output "$work/ob"
expect2 "polar series blocked" "$POLAR" --input "$work/good.fstat" --plot none --output "$work/os"
expect2 "example pvd blocked"  "$EXAMPLE" --output "$work/oe"
"$CG" --help >/dev/null || { echo "FAIL: cg --help"; fail=1; }
"$POLAR" --help >/dev/null || { echo "FAIL: polar --help"; fail=1; }
exit $fail
