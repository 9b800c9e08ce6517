#!/bin/bash
# The local executor end to end (tests/sweep/CMakeLists.txt): a variant that passes, one that
# fails a check and one that hangs past the time limit are each reported as such with their
# logs (exit 1); an interrupted sweep reports the variants it did not run as cancelled (exit 130);
# a variant that falls (a non-finite check value) is reported fell and the sweep finishes; a
# sweep whose process was killed is gathered (--gather) and resumed (--resume) from its folder.
# usage: local_sweep_test.sh SOURCE_DIR BIN_DIR OUT_DIR PYTHON
set -u
src="$1" bin="$2" out="$3" py="$4"
check="$py $src/tests/sweep/check_report.py"
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

# pass, fail, timeout (6 s limit; the hanging variant's sim_host would wait 30 s)
start=$(date +%s%N)
"$bin/ohrp_sweep" "$src/tests/sweep/outcomes.yaml" --out "$out/outcomes" --jobs 3 \
  >"$out/outcomes.md" 2>"$out/outcomes.stderr" &
sweep=$!
# the hanging controller does run (so that its absence afterwards means it was ended)
seen=0
for _ in $(seq 50); do pgrep -f "^ohrp_never_answers" >/dev/null && { seen=1; break; }; sleep 0.1; done
wait $sweep
rc=$?
[ $seen -eq 1 ] || fail "the hanging controller never ran"
took=$(( ($(date +%s%N) - start) / 1000000 ))
cat "$out/outcomes.stderr" "$out/outcomes.md"
[ $rc -eq 1 ] || fail "exit $rc, not 1 (a variant did not pass)"
$check statuses "$out/outcomes" pass fail timeout || fail "statuses"
[ "$($check field "$out/outcomes" 1 base_height_passed)" = false ] || fail "v001's base_height passed"
[ "$($check field "$out/outcomes" 0 base_height_passed)" = true ] || fail "v000's base_height failed"
# killed at 6 s (SIGTERM, the group gone well within the 5 s grace): between 6 and 12 s
wall=$($check field "$out/outcomes" 2 wall_time)
echo "timed-out variant: $wall s wall; the sweep: $took ms"
awk -v w="$wall" 'BEGIN { exit !(w >= 6 && w < 12) }' || fail "the hanging variant ran $wall s, not 6-12 s"
grep -q "killed at the time limit" "$out/outcomes/sweep.csv" || fail "no 'killed at the time limit' detail"
# nothing of the hanging variant is left (its sleep was in the killed group)
[ -z "$(pgrep -f "^ohrp_never_answers")" ] || fail "the hanging controller still runs"
grep -q '^| 2 |.*| timeout |' "$out/outcomes/table.md" || fail "table.md has no timeout row"

# interrupted: one variant at a time, SIGINT while the first (20 s simulated) runs; the one
# running is ended and reported cancelled, and so are the three not started
"$bin/ohrp_sweep" "$src/tests/sweep/long.yaml" --out "$out/interrupted" --jobs 1 \
  >"$out/interrupted.md" 2>"$out/interrupted.stderr" &
pid=$!
sleep 2
kill -INT $pid
wait $pid
rc=$?
cat "$out/interrupted.stderr" "$out/interrupted.md"
[ $rc -eq 130 ] || fail "interrupted sweep: exit $rc, not 130"
$check statuses "$out/interrupted" cancelled cancelled cancelled cancelled || fail "interrupted statuses"
[ -f "$out/interrupted/variants/v000/run/summary.json" ] || fail "the running variant left no summary"
# a variant that falls (its settles value not finite: null in its summary, which aborted
# ohrp_sweep with exit 134 and no sweep.csv) is reported as such and the sweep finishes
"$bin/ohrp_sweep" "$src/tests/sweep/falls.yaml" --out "$out/falls" --jobs 2 \
  >"$out/falls.md" 2>"$out/falls.stderr"
rc=$?
cat "$out/falls.stderr" "$out/falls.md"
[ $rc -eq 1 ] || fail "falling variant: exit $rc, not 1"
$check statuses "$out/falls" pass fell || fail "falling variant statuses"
[ "$($check field "$out/falls" 1 settles)" = nan ] || fail "the fallen variant's settles is not nan"
grep -q "not finite: settles" "$out/falls/sweep.csv" || fail "the detail does not name the non-finite value"

# the submitting process dies (SIGKILL) once the first variant has finished: --gather reports the
# folder as it is, --resume runs only what has not finished
"$bin/ohrp_sweep" "$src/tests/sweep/falls.yaml" --out "$out/resume" --jobs 1 -q >/dev/null 2>&1 &
pid=$!
for _ in $(seq 200); do [ -f "$out/resume/variants/v000/status.json" ] && break; sleep 0.05; done
kill -KILL $pid
wait $pid 2>/dev/null
# the orphaned run of the second variant ends by itself (its own process group)
for _ in $(seq 200); do pgrep -f "$out/resume/variants" >/dev/null || break; sleep 0.05; done
[ -f "$out/resume/variants/v001/status.json" ] && fail "the second variant finished before the kill"
first=$(md5sum < "$out/resume/variants/v000/status.json")
"$bin/ohrp_sweep" --gather "$out/resume" >"$out/gather.md" 2>"$out/gather.stderr"
rc=$?
cat "$out/gather.stderr" "$out/gather.md"
[ $rc -eq 1 ] || fail "--gather: exit $rc, not 1"
$check statuses "$out/resume" pass "not run" || fail "--gather statuses"
"$bin/ohrp_sweep" --resume "$out/resume" --jobs 2 >"$out/resumed.md" 2>"$out/resumed.stderr"
rc=$?
cat "$out/resumed.stderr" "$out/resumed.md"
[ $rc -eq 1 ] || fail "--resume: exit $rc, not 1"
grep -q "resuming .*: 1 of 2 variants to run" "$out/resumed.stderr" || fail "--resume ran other than the unfinished variant"
$check statuses "$out/resume" pass fell || fail "--resume statuses"
[ "$(md5sum < "$out/resume/variants/v000/status.json")" = "$first" ] || fail "--resume ran the finished variant again"
echo "PASS"
