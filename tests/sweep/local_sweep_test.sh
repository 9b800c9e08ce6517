#!/bin/bash
# The local executor end to end (tests/sweep/CMakeLists.txt): a variant that passes, one that
# fails a check and one that hangs past the time limit are each reported as such with their
# logs (exit 1); an interrupted sweep reports the variants it did not run as cancelled (exit 130).
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
echo "PASS"
