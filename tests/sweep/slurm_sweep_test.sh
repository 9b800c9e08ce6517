#!/bin/bash
# The Slurm executor for real (issue 16): a single-node Slurm cluster started here from Debian's
# slurm-wlm and munge (slurm_cluster.sh: private key, socket, ports and folders, torn down on
# exit even on failure), the 9-variant soles sweep run locally and then as one Slurm array job;
# every variant must have run as its own array task, and the gathered reports must agree
# (variants, parameter values, statuses, verdicts and every check value, exactly). Exit 77
# (SKIP, with the reason) when the cluster cannot start, e.g. not root. The sweep is chunked
# (MaxArraySize 5), each task gets 2 CPUs, and a sweep whose submitting process was killed is
# gathered from its folder (--gather) once its job ends.
# usage: slurm_sweep_test.sh SOURCE_DIR BIN_DIR OUT_DIR PYTHON
set -u
src="$1" bin="$2" out="$3" py="$4"
check="$py $src/tests/sweep/check_report.py"
fail() { echo "FAIL: $*"; exit 1; }
# MaxArraySize 5 (array indices 0-4): the 9-variant sweep goes as two array jobs (0-4, 5-8)
export SLURM_MAX_ARRAY_SIZE=5
. "$src/tests/sweep/slurm_cluster.sh"
trap slurm_cluster_stop EXIT
if ! slurm_cluster_start; then
  echo "SKIP: no Slurm cluster: $SLURM_CLUSTER_WHY"
  exit 77
fi
echo "Slurm cluster up in $SLURM_CLUSTER_DIR: $(sinfo -h -N -o '%N %c CPUs %t')"
rm -rf "$out"; mkdir -p "$out"

# the same sweep, locally (two at a time: the machine's cores) and under Slurm
t0=$(date +%s%N)
"$bin/ohrp_sweep" "$src/tests/sweep/soles.yaml" --out "$out/local" --jobs "$(nproc)" \
  >"$out/local.md" 2>"$out/local.stderr" || { cat "$out/local.stderr" "$out/local.md"; fail "local sweep: exit $?"; }
t1=$(date +%s%N)
"$bin/ohrp_sweep" "$src/tests/sweep/soles.yaml" --out "$out/slurm" --slurm --partition test --poll 0.5 \
  >"$out/slurm.md" 2>"$out/slurm.stderr"
rc=$?
t2=$(date +%s%N)
cat "$out/slurm.stderr" "$out/slurm.md"
[ $rc -eq 0 ] || { cat "$SLURM_CLUSTER_DIR"/log/slurm*.log | tail -30; fail "Slurm sweep: exit $rc"; }
tail -1 "$out/local.stderr"
echo "wall time of ohrp_sweep (plots included): local $(( (t1 - t0) / 1000000 )) ms, Slurm $(( (t2 - t1) / 1000000 )) ms"
$check statuses "$out/slurm" pass pass pass pass pass pass pass pass pass || fail "Slurm statuses"
$check same "$out/local" "$out/slurm" 2 || fail "the Slurm report differs from the local one (or not 2 array jobs)"
# each task had the two CPUs of a lock-stepped pair (sbatch --cpus-per-task=2 by default)
cpus="$(scontrol show job "$($check field "$out/slurm" 0 slurm_job)" | grep -o 'NumCPUs=[0-9]*' | sort -u)"
[ "$cpus" = NumCPUs=2 ] || fail "the tasks had '$cpus', not NumCPUs=2"
# each task wrote its own Slurm output and ran on its own segment
for t in 0 1 2 3 4 5 6 7 8; do
  o="$out/slurm/slurm/task_$t.out"
  [ $t -ge 5 ] && o="$out/slurm/slurm/chunk5_task_$((t - 5)).out"
  [ -f "$o" ] || fail "no Slurm output of variant $t ($o)"
  seg="sweep_$($check field "$out/slurm" $t slurm_job)_$t"
  grep -q "\"segment\": \"$seg\"" "$out/slurm/variants/v00$t/status.json" \
    && grep -q "$seg\b" "$out/slurm/variants/v00$t/run/sim_host.stderr" \
    || fail "task $t did not run on segment $seg"
done
test -s "$out/slurm/plot_base_height_vs_contact_params.stiffness.png" || fail "no plot"

# under Slurm too, a failing variant and one hanging past the time limit are reported as such
"$bin/ohrp_sweep" "$src/tests/sweep/outcomes.yaml" --out "$out/outcomes" --slurm --poll 0.5 \
  >"$out/outcomes.md" 2>"$out/outcomes.stderr"
rc=$?
cat "$out/outcomes.md"
[ $rc -eq 1 ] || fail "outcomes under Slurm: exit $rc, not 1"
$check statuses "$out/outcomes" pass fail timeout || fail "outcomes under Slurm"

# the submitting process dies (SIGKILL) once its array job is queued: the job goes on, and
# --gather waits for it and reports every variant (here one that falls: its value not finite)
"$bin/ohrp_sweep" "$src/tests/sweep/falls.yaml" --out "$out/orphan" --slurm --poll 0.5 \
  >/dev/null 2>"$out/orphan.stderr" &
pid=$!
_slurm_wait_for "[ -s '$out/orphan/slurm/jobs.json' ]" 30 || fail "the orphaned sweep never submitted"
kill -KILL $pid
wait $pid 2>/dev/null
"$bin/ohrp_sweep" --gather "$out/orphan" --poll 0.5 >"$out/gathered.md" 2>"$out/gathered.stderr"
rc=$?
cat "$out/gathered.stderr" "$out/gathered.md"
[ $rc -eq 1 ] || fail "--gather of the orphaned Slurm sweep: exit $rc, not 1"
$check statuses "$out/orphan" pass fell || fail "--gather of the orphaned Slurm sweep"

# and a cancelled sweep: SIGINT while the first tasks run cancels the array job (scancel); the
# running variants and the pending ones (which never wrote a status: Slurm's state says what
# became of them) are all reported cancelled
"$bin/ohrp_sweep" "$src/tests/sweep/long.yaml" --out "$out/cancelled" --slurm --poll 0.5 \
  >"$out/cancelled.md" 2>"$out/cancelled.stderr" &
pid=$!
_slurm_wait_for "[ -n \"\$(squeue -h -t RUNNING)\" ]" 30 || fail "the long sweep's tasks never ran"
sleep 1
kill -INT $pid
wait $pid
rc=$?
cat "$out/cancelled.stderr" "$out/cancelled.md"
[ $rc -eq 130 ] || fail "cancelled sweep under Slurm: exit $rc, not 130"
$check statuses "$out/cancelled" cancelled cancelled cancelled cancelled || fail "cancelled under Slurm"
[ -z "$(squeue -h)" ] || fail "jobs left in the queue: $(squeue -h)"
echo "PASS"
