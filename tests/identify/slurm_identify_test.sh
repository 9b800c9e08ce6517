#!/bin/bash
# ohrp identify --slurm (issue 16: identification uses the sweep): on a single-node Slurm cluster
# started here (tests/sweep/slurm_cluster.sh), the identification of one recording run with the
# local executor and with the Slurm one must give the same identify.json (estimates, every run's
# K, D, frequency and decay, exactly: the runs are deterministic), each stage as its own Slurm
# array job whose tasks ran the stage's variants (sweep.csv: slurm_job, slurm_task). The
# recording is sim_host's of scenarios/rocking_fig12.yaml with soles 2e6 N/m and 45 s/m (what
# is compared is the executors, not the recovery: tests/identify/robot_test.cc does that).
# Exit 77 (SKIP, with the reason) when the cluster cannot start, e.g. not root.
# usage: slurm_identify_test.sh SOURCE_DIR BIN_DIR OUT_DIR PYTHON
set -u
src="$1" bin="$2" out="$3" py="$4"
fail() { echo "FAIL: $*"; exit 1; }
. "$src/tests/sweep/slurm_cluster.sh"
trap slurm_cluster_stop EXIT
if ! slurm_cluster_start; then
  echo "SKIP: no Slurm cluster: $SLURM_CLUSTER_WHY"
  exit 77
fi
rm -rf "$out"; mkdir -p "$out"

# the recording
{ cat "$src/scenarios/rocking_fig12.yaml"; echo "contact_params: {stiffness: 2000000, damping: 45}"; } > "$out/robot.yaml"
"$bin/ohrp_run" "$out/robot.yaml" --out "$out/robot" --no-plot -q > "$out/robot.out" 2>&1 ||
  { cat "$out/robot.out"; fail "ohrp_run of the recording: exit $?"; }

t0=$(date +%s%N)
"$bin/ohrp_identify" "$out/robot/log.csv" --out "$out/local" --jobs "$(nproc)" > "$out/local.out" 2>&1 ||
  { cat "$out/local.out"; fail "local identify: exit $?"; }
t1=$(date +%s%N)
"$bin/ohrp_identify" "$out/robot/log.csv" --out "$out/slurm" --slurm --partition test --poll 0.5 \
  > "$out/slurm.out" 2>&1
rc=$?
t2=$(date +%s%N)
grep -v '^ohrp_sweep: \[' "$out/slurm.out"
[ $rc -eq 0 ] || { cat "$SLURM_CLUSTER_DIR"/log/slurm*.log | tail -30; fail "identify --slurm: exit $rc"; }
echo "wall time of ohrp_identify: local (--jobs $(nproc)) $(( (t1 - t0) / 1000000 )) ms, Slurm $(( (t2 - t1) / 1000000 )) ms"

"$py" - "$out/local" "$out/slurm" <<'PY' || fail "the Slurm identification differs from the local one"
import csv, json, os, sys
local, slurm = (json.load(open(os.path.join(d, "identify.json"))) for d in sys.argv[1:3])
bad = []
for key in ("closed_form", "refined", "recorded", "final", "lag"):
    if local[key] != slurm[key]:
        bad.append("%s: local %s, Slurm %s" % (key, local[key], slurm[key]))
fields = ("stage", "k", "d", "frequency", "log_decrement")
if [[r[f] for f in fields] for r in local["runs"]] != [[r[f] for f in fields] for r in slurm["runs"]]:
    bad.append("the runs differ")
jobs = set()
for s in slurm["sweeps"]:
    if s["executor"] != "slurm" or not s.get("slurm_job"):
        bad.append("stage %s: not a Slurm job: %s" % (s["stage"], s))
        continue
    jobs.add(s["slurm_job"])
    rows = list(csv.DictReader(open(os.path.join(s["dir"], "sweep.csv"))))
    if len(rows) != s["variants"]:
        bad.append("stage %s: %d rows in sweep.csv for %d variants" % (s["stage"], len(rows), s["variants"]))
    for r in rows:
        if r["slurm_job"] != s["slurm_job"] or r["slurm_task"] != r["variant"]:
            bad.append("stage %s variant %s ran as job %s task %s" % (s["stage"], r["variant"], r["slurm_job"], r["slurm_task"]))
if [s["stage"] for s in slurm["sweeps"]] != ["nominal", "k", "d", "final"] or len(jobs) != 4:
    bad.append("not one Slurm job per stage: %s" % slurm["sweeps"])
print("\n".join(bad) if bad else "same identification locally and under Slurm: K %.6g, D %.6g; %d runs in %d array jobs"
      % (slurm["refined"]["k"], slurm["refined"]["d"], len(slurm["runs"]), len(jobs)))
sys.exit(1 if bad else 0)
PY
echo "PASS"
