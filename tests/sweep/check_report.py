#!/usr/bin/env python3
"""Checks of a sweep's report for the sweep tests (tests/sweep/*.sh).

    check_report.py statuses SWEEP_DIR S0 S1 ...     each variant's status, in order; every
                                                     variant not passing names an existing log folder
    check_report.py same LOCAL_DIR SLURM_DIR [JOBS]  the same variants, parameter values, statuses,
                                                     verdicts and check values (exactly), and the
                                                     Slurm rows ran in JOBS array jobs (default 1),
                                                     each variant as task <variant - the job's first>
    check_report.py field SWEEP_DIR VARIANT COLUMN   prints one cell of sweep.csv
Exit 0 when it holds, 1 with the differences printed.
"""
import csv
import os
import sys

RUN_COLUMNS = {"real_time_factor", "wall_time", "host", "slurm_job", "slurm_task", "log_dir", "detail"}


def rows(folder):
    with open(os.path.join(folder, "sweep.csv"), newline="") as f:
        return list(csv.DictReader(f))


def main(argv):
    what = argv[1]
    if what == "statuses":
        r = rows(argv[2])
        got = [x["status"] for x in r]
        bad = []
        if got != argv[3:]:
            bad.append(f"statuses {got}, expected {argv[3:]}")
        for x in r:
            if x["status"] != "pass" and not os.path.isdir(x["log_dir"]):
                bad.append(f"variant {x['variant']}: its log folder '{x['log_dir']}' does not exist")
        print("\n".join(bad))
        return 1 if bad else 0
    if what == "same":
        a, b = rows(argv[2]), rows(argv[3])
        bad = []
        if len(a) != len(b) or len(a) == 0:
            bad.append(f"{len(a)} local rows, {len(b)} Slurm rows")
        expected_jobs = int(argv[4]) if len(argv) > 4 else 1
        jobs = {y["slurm_job"] for y in b}
        if len(jobs) != expected_jobs or "" in jobs:
            bad.append(f"the Slurm rows name array jobs {jobs}, not {expected_jobs}")
        first = {}  # each job's first variant: its offset
        for y in b:
            first[y["slurm_job"]] = min(first.get(y["slurm_job"], 10**9), int(y["variant"]))
        for x, y in zip(a, b):
            for k in x:
                if k in RUN_COLUMNS:
                    continue
                if x[k] != y.get(k):
                    bad.append(f"variant {x['variant']}: {k} is {x[k]} locally, {y.get(k)} under Slurm")
            if y["slurm_task"] != str(int(y["variant"]) - first.get(y["slurm_job"], 0)):
                bad.append(f"variant {y['variant']} ran as Slurm task '{y['slurm_task']}' of job {y['slurm_job']}")
            if x["slurm_task"] or x["slurm_job"]:
                bad.append(f"variant {x['variant']} of the local sweep names a Slurm task")
        print("\n".join(bad))
        return 1 if bad else 0
    if what == "field":
        for x in rows(argv[2]):
            if x["variant"] == argv[3]:
                print(x[argv[4]])
                return 0
        return 1
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
