"""The study commands from Python: sweep, device, calibrate and the build's description, each the
command line's own function in the compiled module."""

import json
import math
import os

from ._arguments import _count, _out_folder, _study_sets
from ._native import _core
from ._progress import _CaseProgress, _run


def build():
    """The build of the compiled core, as every run's build.json records it and `vppdem
    --version` prints it: {"commit": git describe of its sources, "id": 16 hex digits, the same
    for the same sources built the same way}."""
    return dict(_core.build())


def sweep(study_path, out, sets=None, seeds=0, jobs=0, quiet=True, settings=None, progress=None, backend="cpu",
          mix_builds=False, publish=None, report_only=False):
    """`vppdem sweep STUDY --out OUT`: runs (or resumes) the study; returns the failed cases'
    count. sets: ["key=value", ...] or `settings` (a dict) fixed for every case.
    backend: "cpu", "batch" or "cuda", as the command's --backend (docs/studies.md, docs/gpu.md).
    jobs: cases at once, as --jobs (0: the free cores / threads per case; >= 0).
    mix_builds: continue in a folder whose cases another build ran, as --mix-builds (refused,
    ConfigError, without it).
    publish: a results folder, as --publish: the finished cases' small records and the tables
    are kept there, and records there that `out` lacks are put back first (docs/studies.md).
    report_only: as --report-only: runs nothing, writes the tables from the cases finished in
    `out` (which must exist, else ConfigError naming it).
    progress: None, True (a tqdm bar over the cases, else a line per case on stderr) or a
    callable progress(done, total, case) called after each finished case. Ctrl-C, or an
    exception of the callable, stops the sweep and is raised; finished cases stay, and the
    same call resumes it."""
    extra = _study_sets(sets, settings)
    return _run(_core.sweep, progress, os.fspath(study_path), _out_folder("out", out), extra, int(seeds),
                _count("jobs", jobs, 0, 2**31 - 1), bool(quiet), callback=_CaseProgress, backend=str(backend),
                mix_builds=bool(mix_builds), publish=os.fspath(publish) if publish is not None else "",
                report_only=bool(report_only))


def device(device_file, out, sets=None, settings=None, from_checkpoint=None, overwrite=False, quiet=True,
           checkpoint_every=60.0):
    """`vppdem device FILE --out OUT`: builds the device of the device file (membrane and tools
    from meshes, docs/devices.md), runs (or resumes: the same call again, or from_checkpoint=a
    run.ckpt) its stages fill, seal, press, vacuum, load, and writes its records to `out`.
    sets: ["key=value", ...] or `settings` (a dict), as the command's --set. Returns summary.json's
    numbers as a dict (holding_force [N], volume_change [-], cycle_stiffness [N/m], ...).
    Bad keys and values raise vppdem.ConfigError, a bad mesh RuntimeError, before anything is
    written. Ctrl-C stops the run at its next step with a checkpoint in `out` and raises
    KeyboardInterrupt; the same call resumes it."""
    extra = _study_sets(sets, settings)
    if not float(checkpoint_every) > 0.0 or not math.isfinite(float(checkpoint_every)):
        raise ValueError(f"checkpoint_every = {checkpoint_every!r}: must be a finite number of seconds > 0")
    return _core.device(os.fspath(device_file), _out_folder("out", out), extra,
                        os.fspath(from_checkpoint) if from_checkpoint is not None else "", bool(overwrite),
                        bool(quiet), float(checkpoint_every))


def calibrate(study_path, experiment, out, sets=None, seeds=0, jobs=0, quiet=True, settings=None,
              displacement_unit="m", force_unit="N", compression_negative=False, simulated_force="force_zeroed",
              points=50, plot=False, time_column="time", displacement_column="displacement", force_column="force",
              progress=None, mix_builds=False):
    """`vppdem calibrate STUDY --experiment EXP --out OUT`: returns calibration.json as a dict;
    raises RuntimeError when the calibration failed (cases failed or none could be compared).
    The keywords are the command's options (--displacement-unit, --force-column, ...);
    progress and Ctrl-C as in sweep()."""
    if displacement_unit not in ("m", "mm") or force_unit not in ("N", "kN"):
        raise ValueError("displacement_unit: 'm' or 'mm'; force_unit: 'N' or 'kN'")
    extra = _study_sets(sets, settings)
    rc = _run(_core.calibrate, progress, os.fspath(study_path), os.fspath(experiment), _out_folder("out", out), extra,
              int(seeds), _count("jobs", jobs, 0, 2**31 - 1), bool(quiet), displacement_unit, force_unit,
              bool(compression_negative), simulated_force,
              int(points), bool(plot), time_column, displacement_column, force_column, callback=_CaseProgress,
              mix_builds=bool(mix_builds))
    path = os.path.join(os.fspath(out), "calibration.json")
    if rc != 0 or not os.path.exists(path):
        raise RuntimeError(f"calibrate: no calibration (exit status {rc}); see {out}")
    with open(path) as f:
        return json.load(f)


# vppdem.Study: a study file and its output folder as one object (src/python/vppdem/study.py); at the
# end, as it uses sweep() and calibrate() above.
