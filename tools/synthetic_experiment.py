#!/usr/bin/env python3
"""A synthetic "measured" loop from a damper run, written as a test rig would: for calibrations
that must recover a known friction (docs/studies.md, "Calibration that could fail").

usage: synthetic_experiment.py FORCES.csv OUT.csv [--disp-noise M] [--force-noise N] [--seed S]
                               [--offset MM]

Reads a `vppdem damper` forces.csv (time, displacement [m], force_zeroed [N], compression
positive) and writes OUT.csv with the columns `t_s,stroke_mm,load_kN`: stroke in mm from an
arbitrary origin (--offset, default 12.5 mm), load in kN, both compression negative, with
Gaussian noise of standard deviation --disp-noise [m] (default 2e-6) and --force-noise [N]
(default 0.4) from the random seed --seed (default 7). Read it back with
  vppdem calibrate ... --experiment OUT.csv --time-column t_s --displacement-column stroke_mm
      --force-column load_kN --displacement-unit mm --force-unit kN --compression-negative
The file is written to a temporary name and renamed. Runs under /usr/bin/python3 (numpy).
"""
import argparse
import os
import sys

import numpy as np

# The package's records (vppdem/records.py): one CSV reader and one way to stop for the tools.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "src", "python"))
from vppdem.records import fail, read_table  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description="synthetic rig record from a damper run")
    ap.add_argument("forces")
    ap.add_argument("out")
    ap.add_argument("--disp-noise", type=float, default=2e-6, help="[m] standard deviation")
    ap.add_argument("--force-noise", type=float, default=0.4, help="[N] standard deviation")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--offset", type=float, default=12.5, help="[mm] origin of the stroke")
    a = ap.parse_args()
    _, rows = read_table(a.forces)
    if not rows or "force_zeroed" not in rows[0]:
        fail(f"{a.forces} is no damper forces.csv (no force_zeroed column)")
    rng = np.random.default_rng(a.seed)
    t = np.array([float(r["time"]) for r in rows])
    d = np.array([float(r["displacement"]) for r in rows]) + rng.normal(0.0, a.disp_noise, len(rows))
    F = np.array([float(r["force_zeroed"]) for r in rows]) + rng.normal(0.0, a.force_noise, len(rows))
    tmp = a.out + ".part"
    with open(tmp, "w") as f:
        f.write(f"# synthetic record from {os.path.abspath(a.forces)}: noise {a.disp_noise} m, {a.force_noise} N, "
                f"seed {a.seed}\nt_s,stroke_mm,load_kN\n")
        for k in range(len(rows)):
            f.write(f"{t[k]:.9g},{-(a.offset + 1e3 * d[k]):.9g},{-1e-3 * F[k]:.9g}\n")
    os.replace(tmp, a.out)
    print(f"wrote {a.out} ({len(rows)} samples)")


if __name__ == "__main__":
    main()
