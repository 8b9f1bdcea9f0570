#!/usr/bin/env bash
# Bad-input probes: runs BadInputProbe (path in $1) with every refused case and checks that it exits
# with code 2 and prints exactly one line on stderr, "BadInputProbe: error: ...", naming the parameter;
# and that no *.tmp file is left behind. Usage: bash BadInputProbe.sh PATH/TO/BadInputProbe
set -u
probe="$1"
work="$(pwd)/bad_input_probe_work"
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_refused KEYWORD(extended regex, case-insensitive) ARGS...
expect_refused() {
    local keyword="$1"
    shift
    "$probe" --quiet --output out "$@" > stdout.txt 2> stderr.txt
    local rc=$?
    local lines
    lines=$(wc -l < stderr.txt)
    local msg
    msg=$(cat stderr.txt)
    if [ "$rc" -ne 2 ]; then
        fail "[$*] exit code $rc (expected 2); stderr: $msg"
    elif [ "$lines" -ne 1 ]; then
        fail "[$*] stderr has $lines lines (expected 1): $msg"
    elif ! grep -q '^BadInputProbe: error: ' stderr.txt; then
        fail "[$*] stderr does not start with 'BadInputProbe: error: ': $msg"
    elif ! grep -qiE -- "$keyword" stderr.txt; then
        fail "[$*] message does not name '$keyword': $msg"
    else
        echo "ok   [$*] -> $msg"
    fi
    if [ -n "$(find . -name '*.tmp')" ]; then
        fail "[$*] left temporary files: $(find . -name '*.tmp' | tr '\n' ' ')"
        find . -name '*.tmp' -delete
    fi
}

# ---- a valid run first (exit 0), which also provides a restart file --------------------------------
if ! "$probe" --quiet --output out --name good > stdout.txt 2> stderr.txt; then
    fail "valid run failed: $(cat stderr.txt)"
fi
[ -f out/good.restart ] || fail "valid run wrote no out/good.restart"

# ---- parameters ---------------------------------------------------------------------------------------
expect_refused 'radius' --radius -1e-3
expect_refused 'radius' --radius 0
expect_refused 'density' --density -2000
expect_refused 'density' --density 0
expect_refused 'stiffness' --stiffness -1000
expect_refused 'stiffness' --stiffness 0
expect_refused 'restitution' --restitution 0
expect_refused 'restitution' --restitution -0.5
expect_refused 'restitution' --restitution 1.5
expect_refused 'restitution' --contact_law hertz --restitution 1.5
expect_refused 'mu' --mu -0.1
expect_refused 'phi_f' --contact_law luding --phi_f 1.5
expect_refused 'phi_f' --contact_law luding --phi_f -0.1
expect_refused 'k1' --contact_law luding --k1 5000
expect_refused 'dt' --dt 1e-4
# values that would make a run last forever: a femtosecond contact, a million steps per contact
expect_refused 't_c .* below 1e-15' --stiffness 1e300
expect_refused 'dt .* below t_c/1e6' --dt 1e-300
expect_refused 'overlap' --gap -2e-4
expect_refused 'no_such_flag' --no_such_flag 1
expect_refused 'contact_law|contact law' --contact_law no_such_law

# ---- NaN during a run: names particle and time; the last finite restart reads back ---------------------
# dt 4e-6 s, output every 10 steps: the NaN appears after a plain step (115) and after an output step (110),
# whose restart must not be the one with the NaN in it.
for nanStep in 115 110; do
    name="nan$nanStep"
    expect_refused 'particle 1.*t = ' --name "$name" --dt 4e-6 --save_every 4e-5 --fstat 1 --nan_step "$nanStep"
    if [ ! -f "out/$name.restart" ]; then
        fail "NaN run (step $nanStep) left no out/$name.restart"
    elif ! "$probe" --quiet --output out --name "${name}_resumed" --restart "out/$name.restart" --nan_step -1 \
        > stdout.txt 2> stderr.txt; then
        fail "restart file of the NaN run (step $nanStep) does not read back: $(cat stderr.txt)"
    else
        echo "ok   out/$name.restart reads back and the run completes"
    fi
done

# ---- restart files --------------------------------------------------------------------------------------
cp out/good.restart bad_header.restart
sed -i '1s/^PowderDPM-restart/NotPowderDPM-restart/' bad_header.restart
expect_refused 'header' --restart bad_header.restart

cp out/good.restart version.restart
sed -i '1s/ [0-9]*$/ 99/' version.restart
"$probe" --rehash version.restart || fail "rehash failed"
expect_refused 'version' --restart version.restart

head -c 1500 out/good.restart > truncated.restart
expect_refused 'truncated|checksum' --restart truncated.restart

cp out/good.restart edited.restart
sed -i 's/^species 1$/species 1 /; /^particles /{n;s/^\(.\)/9\1/}' edited.restart
cmp -s edited.restart out/good.restart && fail "edited.restart was not changed"
expect_refused 'checksum' --restart edited.restart

cp out/good.restart foreign.restart
sed -i 's/^program BadInputProbe$/program OtherDriver/' foreign.restart
"$probe" --rehash foreign.restart || fail "rehash failed"
expect_refused 'OtherDriver' --restart foreign.restart

expect_refused 'contact.law' --restart out/good.restart --contact_law hertz

# nothing may follow the checksum: a line appended, or text after the hash on its line
cp out/good.restart appended.restart
echo "garbage line" >> appended.restart
expect_refused 'after the checksum' --restart appended.restart
cp out/good.restart end_suffix.restart
sed -i '$ s/$/XYZ/' end_suffix.restart
expect_refused 'after the checksum' --restart end_suffix.restart

# edited values behind a valid (resealed) checksum: refused by name, not run
# resealed NAME SED-EXPRESSION: out/good.restart edited by the expression and resealed, as NAME.restart
resealed() {
    cp out/good.restart "$1.restart"
    sed -i "$2" "$1.restart"
    cmp -s "$1.restart" out/good.restart && fail "$1.restart: the edit '$2' changed nothing"
    "$probe" --rehash "$1.restart" || fail "rehash of $1.restart failed"
}
resealed time_neg 's/^time [^ ]* step/time -1 step/'
expect_refused 'invalid time' --restart time_neg.restart
resealed step_neg 's/ step [0-9]* dt / step -5 dt /'
expect_refused 'invalid step' --restart step_neg.restart
resealed output_nan 's/^output \([0-9]*\) [^ ]* /output \1 nan /'
expect_refused 'invalid output' --restart output_nan.restart
resealed output_minf 's/^output \([0-9]*\) [^ ]* /output \1 -inf /'
expect_refused 'invalid output' --restart output_minf.restart
resealed output_past 's/^output \([0-9]*\) [^ ]* /output \1 -1e20 /'
expect_refused 'invalid output' --restart output_past.restart
# a restart time at which the step is below the clock's resolution (t + dt == t: the run would never end)
resealed time_huge 's/^time [^ ]* step/time 1e15 step/; s/^output \([0-9]*\) [^ ]* /output \1 2e15 /'
expect_refused "clock's resolution" --restart time_huge.restart --time_max 3e15
resealed gravity_nan 's/^gravity 0 0 -9.81/gravity 0 nan -9.81/'
expect_refused 'gravity' --restart gravity_nan.restart
resealed box_change_inf 's/^\(box .*\) 0$/\1 inf/'
expect_refused 'box record' --restart box_change_inf.restart
resealed wall_velocity_nan 's/^\(plane 0 - \([^ ]* \)\{9\}\)[^ ]*/\1nan/'
expect_refused 'wall record' --restart wall_velocity_nan.restart
# a finite velocity whose square overflows: the .ene file got an 'inf' row before (exit 2 only later)
resealed velocity_huge '/^particles /{n;s/^\([^ ]* [^ ]* [^ ]*\) [^ ]* /\1 1e300 /}'
expect_refused 'particle record 0' --restart velocity_huge.restart --time_max 0.004
grep -qsw inf out/*.ene && fail "an .ene row with inf was written"
resealed stiffness_nan '/^species /{n;n;s/^0 0 1 [^ ]*/0 0 1 nan/}'
expect_refused 'contact parameters' --restart stiffness_nan.restart
resealed skin_nan 's/^neighbours [^ ]* /neighbours nan /'
expect_refused 'inconsistent neighbour' --restart skin_nan.restart
resealed x0_nan '/^x0 /{n;s/^[^ ]*/nan/}'
expect_refused 'inconsistent neighbour' --restart x0_nan.restart
# the neighbour section's history size edited together with its history arrays (sizes consistent
# with each other, not with the law line's 4 doubles per contact): the pair loops would read past
# (2 per pair) or misread (5 per pair) the histories
grep -q '^law linear 4$' out/good.restart || fail "good.restart does not name 'law linear 4'"
resealed history_two 's/^\(neighbours [^ ]* [^ ]*\) 4 /\1 2 /; /^history 4$/{N;s/^history 4\n\([^ ]*\) \([^ ]*\) .*$/history 2\n\1 \2/}'
grep -q '^history 2$' history_two.restart || fail "history_two.restart: the history array was not rewritten"
expect_refused 'history size 2 differs' --restart history_two.restart --time_max 0.004
resealed history_five 's/^\(neighbours [^ ]* [^ ]*\) 4 /\1 5 /; /^history 4$/{N;s/^history 4\n\(.*\)$/history 5\n\1 0/}'
grep -q '^history 5$' history_five.restart || fail "history_five.restart: the history array was not rewritten"
expect_refused 'history size 5 differs' --restart history_five.restart --time_max 0.004
# slab starts that do not begin at 0 (the first slab's pairs would be skipped and a later one's read twice)
resealed slab_start_one '/^slabStart 2$/{n;s/^0 /1 /}'
expect_refused 'inconsistent neighbour' --restart slab_start_one.restart --time_max 0.004
resealed velocity_inf '/^particles /{n;s/^\([^ ]* [^ ]* [^ ]*\) [^ ]*/\1 inf/}'
expect_refused 'particle record 0' --restart velocity_inf.restart
resealed fixed_two '/^particles /{n;s/ [01]$/ 2/}'
expect_refused 'particle record 0' --restart fixed_two.restart
resealed wall_point_nan 's/^plane 0 - [^ ]*/plane 0 - nan/'
expect_refused 'plane wall' --restart wall_point_nan.restart
resealed wall_normal_long 's/^\(plane 0 - \([^ ]* \)\{3\}\)\([^ ]*\) \([^ ]*\) \([^ ]*\)/\1 3 4 12/'
expect_refused 'plane wall' --restart wall_normal_long.restart

# the RUN.fstat output cannot be completed (a directory is in its place): exit 2, no .tmp left
mkdir -p out/blocked.fstat
expect_refused 'blocked.fstat' --name blocked --fstat 1
rmdir out/blocked.fstat

if [ "$failures" -ne 0 ]; then
    echo "BadInputProbe.sh: $failures failure(s)"
    exit 1
fi
echo "BadInputProbe.sh: all probes passed"
