"""Run folders (what ohrp_run writes: log.csv, summary.json, sim_summary.json...) as numpy.

    run = ohrp.load_run("build/runs/stand")
    t, z = run.log["time"], run.log["base_z"]
    print(run.summary["verdict"], run.joint("RLEG_KNEE").max())
"""

import csv
import json
import os

import numpy as np


def read_log(path, required=()):
    """A CSV log with a header row (sim_host's and hw_driver's data logs, walk.csv...) as a
    dict of column name -> float64 array, in the file's column order. Raises ValueError naming
    the file and line of a row that is not numbers or has the wrong number of fields, or the
    `required` columns that are missing."""
    with open(path, newline="") as f:
        rows = csv.reader(f)
        try:
            names = next(rows)
        except StopIteration:
            raise ValueError("%s: empty file (a log starts with a header row)" % path)
        missing = [c for c in required if c not in names]
        if missing:
            raise ValueError("%s: missing column(s) %s (the header has %s)"
                             % (path, ", ".join(missing), ",".join(names)))
        data = []
        for line, row in enumerate(rows, start=2):
            if len(row) != len(names):
                raise ValueError("%s:%d: %d fields, the header has %d"
                                 % (path, line, len(row), len(names)))
            try:
                data.append([float(v) for v in row])
            except ValueError as e:
                raise ValueError("%s:%d: %s" % (path, line, e))
    table = np.array(data, dtype=np.float64).reshape(len(data), len(names))
    return {n: table[:, i] for i, n in enumerate(names)}


class Run:
    """A finished run's folder: log (dict of arrays), summary and sim_summary (dicts)."""

    def __init__(self, folder):
        if not os.path.isdir(folder):
            raise FileNotFoundError("%s: not a run folder (ohrp_run --out names one)" % folder)
        self.folder = folder
        self.summary = self._json("summary.json")
        self.sim_summary = self._json("sim_summary.json")
        log = os.path.join(folder, "log.csv")
        self.log = read_log(log) if os.path.exists(log) else {}

    def _json(self, name):
        path = os.path.join(self.folder, name)
        if not os.path.exists(path):
            return {}
        with open(path) as f:
            return json.load(f)

    @property
    def time(self):
        return self.log["time"]

    def joint(self, name, what="q"):
        """One joint's column: what = q (position), qref (reference) or tau (torque)."""
        key = "%s_%s" % (what, name)
        if key not in self.log:
            joints = sorted(k[2:] for k in self.log if k.startswith("q_"))
            raise KeyError("%s: no column '%s' (joints: %s)"
                           % (self.folder, key, ", ".join(joints)))
        return self.log[key]


def load_run(folder):
    return Run(folder)
