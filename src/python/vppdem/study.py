"""``vppdem.Study``: a study file (docs/studies.md) and its output folder as one object.

A thin front to what exists: ``run()`` is ``vppdem.sweep``, ``report()`` is ``vppdem.sweep`` with
``report_only`` (the command's ``--report-only``), ``cases()`` the command's ``--list`` (the
compiled module's ``study_cases``), ``calibrate()`` is ``vppdem.calibrate``; ``summary()``,
``cases_summary()`` and ``paired()`` read the tables back with the csv module. Nothing here
changes what the engine does or writes.
"""

import csv
import errno
import os

from ._arguments import _count, _study_sets
from ._native import _core
from ._runs import calibrate as _calibrate, sweep as _sweep

# Columns that are text whatever they hold (names, messages), never numbers.
_TEXT_COLUMNS = frozenset({"case", "cases", "status", "warnings", "key", "group", "quantity", "folder", "folders",
                           "message"})

# The Study's own settings: not to be given again to calibrate().
_OWN = ("sets", "seeds", "settings", "out", "study_path")


def _cell(column, text):
    """A table's cell: None when empty, a float when it parses as one, else the text."""
    if text is None or text == "":
        return None
    if column in _TEXT_COLUMNS:
        return text
    try:
        return float(text)
    except ValueError:
        return text


def _read_table(path):
    with open(path, newline="") as f:
        return [{k: _cell(k, v) for k, v in row.items()} for row in csv.DictReader(f)]


class Study:
    """A study (docs/studies.md) and its output folder.

    ``path``: the study file (TOML); a missing file raises FileNotFoundError naming it.
    ``out``: the folder of the cases and tables (the command's --out; a run into it resumes).
    ``sets`` (["key=value", ...], as --set) and ``settings`` (a dict of dotted keys): fixed
    overrides of every case, as in ``vppdem.sweep`` (a key in both is refused, ValueError).
    ``seeds``: 0 (the study file's own ``seeds``, if any) or N in 1..1000, as --seeds.
    ``publish``: a results folder, as --publish (None: none).

    A device study file (the key ``device``; docs/devices.md, "Studies") works the same way:
    ``cases()`` lists its runs (with ``case``, ``seed`` and ``overrides`` besides), ``run()`` and
    ``report()`` are ``vppdem sweep`` on it, ``summary()`` reads its summary.csv (case, seed,
    folder, the numbers of each run's summary.json, status, message), ``cases_summary()`` its
    summary_cases.csv (per case the mean, sd and 95% interval of each number over the seeds).

    Units are those of the records (docs/studies.md, "Outputs"): W [J/m^2], dissipated_energy [J],
    peak_force [N], run_seconds [s]; the grid values in the damper config's units (docs/config.md).
    """

    def __init__(self, path, out, sets=None, settings=None, seeds=0, publish=None):
        if path is None or out is None:
            raise ValueError(f"Study: {'path' if path is None else 'out'} is required (a study file and an output "
                             "folder, as `vppdem sweep STUDY --out DIR`)")
        self.path = os.fspath(path)
        if not os.path.exists(self.path):
            raise FileNotFoundError(errno.ENOENT, "study file not found", self.path)
        if not os.path.isfile(self.path):
            raise IsADirectoryError(errno.EISDIR, "study file is not a file", self.path)
        self.out = os.fspath(out)
        if not self.out:
            raise ValueError("Study: out = '': an output folder is required")
        self.seeds = _count("seeds", seeds, 0, 1000, ", 0 for the study file's own seeds")
        if sets is not None and not isinstance(sets, (str, bytes, dict)):
            sets = list(sets)  # an iterator once, not consumed by the check
        self._extra = _study_sets(sets, settings)  # refuses bad types and a key in both, now
        self.sets = sets
        self.settings = None if settings is None else dict(settings)
        self.publish = None if publish is None else os.fspath(publish)

    def __repr__(self):
        return f"vppdem.Study({self.path!r}, out={self.out!r})"

    def cases(self):
        """The study's cases as ``vppdem sweep STUDY --out DIR --list`` gives them (checked, none
        run): a list of dicts in the sweep's order, with ``index`` (1-based, as listed), ``name``
        (the case's folder name), ``folder`` (its path under ``out``), ``group`` (the 1-based
        number of its preparation), ``prepares`` (True: it prepares that sample) and
        ``branches_from`` (the name of the case whose prepared sample it starts from; None when it
        prepares). A bad study raises vppdem.ConfigError with the command's message."""
        rows = _core.study_cases(self.path, self._extra, self.seeds)
        for r in rows:
            r["folder"] = os.path.join(self.out, r["name"])
        return rows

    def report(self, quiet=True):
        """``vppdem sweep STUDY --out DIR --report-only``: runs nothing, and writes summary.csv,
        summary_cases.csv (and, with seeds, summary_paired.csv) from the cases finished in
        ``out``, the others with status "not run" (published too with ``publish``). Returns
        summary() of the new tables. ``out`` must exist (FileNotFoundError naming it).
        quiet=False prints the line "N of M cases finished" on stderr."""
        if not os.path.isdir(self.out):
            raise FileNotFoundError(errno.ENOENT, "Study.report(): no output folder (run() first)", self.out)
        _sweep(self.path, self.out, sets=self.sets, seeds=self.seeds, quiet=quiet, settings=self.settings,
               publish=self.publish, report_only=True)
        return self.summary()

    # --- the module's functions -------------------------------------------------------------------
    def run(self, jobs=0, backend="cpu", progress=None, mix_builds=False, quiet=True):
        """Runs (or resumes) the study into ``out``: ``vppdem.sweep`` with this study's path, out,
        sets, settings, seeds and publish. jobs: cases at once (0: the free cores / threads per
        case); backend "cpu", "batch" or "cuda"; progress None, True or progress(done, total, case).
        Returns the failed cases' count (0: all finished)."""
        return _sweep(self.path, self.out, sets=self.sets, seeds=self.seeds, jobs=jobs, quiet=quiet,
                      settings=self.settings, progress=progress, backend=backend, mix_builds=mix_builds,
                      publish=self.publish)

    def calibrate(self, experiment, **kwargs):
        """``vppdem.calibrate(path, experiment, out, ...)`` with this study's sets, settings and
        seeds: runs (or resumes) the study into ``out`` and compares every case with the
        experiment's loop. kwargs: vppdem.calibrate's (jobs, quiet, displacement_unit,
        force_unit, force_column, simulated_force, points, plot, progress, mix_builds, ...).
        Returns calibration.json as a dict (best case, misfit, ...)."""
        given = sorted(k for k in kwargs if k in _OWN)
        if given:
            raise ValueError(f"Study.calibrate(): {', '.join(given)} belong to the Study (give them to "
                             "vppdem.Study(...)), not to calibrate()")
        return _calibrate(self.path, experiment, self.out, sets=self.sets, seeds=self.seeds, settings=self.settings,
                          **kwargs)

    # --- the tables ---------------------------------------------------------------------------------
    def _table(self, name, missing_ok=False):
        path = os.path.join(self.out, name)
        if not os.path.exists(path):
            if missing_ok:
                return []
            raise FileNotFoundError(errno.ENOENT, f"no {name} yet (run() or report() first)", path)
        return _read_table(path)

    def summary(self):
        """summary.csv as a list of dicts, one per run (grid order): the swept keys, W [J/m^2],
        dissipated_energy [J], peak_force [N], run_seconds [s], status ("ok", "failed: ...",
        "not run"), case (folder name), W_settled [J/m^2], settled_cycles, first_settled_cycle,
        friction_share, damping_share, grains, packing_fraction, warnings. Numbers are floats,
        empty cells None, text (status, case, warnings) str. FileNotFoundError when absent."""
        return self._table("summary.csv")

    def cases_summary(self):
        """summary_cases.csv as a list of dicts, one per case over its seeds: the swept keys but the
        seed, seeds, ok, then Q_n, Q_mean, Q_sd, Q_ci95 for Q in W, W_settled, peak_force,
        dissipated_energy, friction_share, damping_share, packing_fraction (Q's units), cases.
        A device study's: case, seeds, ok, then Q_n, Q_mean, Q_sd, Q_ci95 for each number of its
        summary.csv, folders. Numbers as floats, empty cells None. FileNotFoundError when absent."""
        return self._table("summary_cases.csv")

    def paired(self):
        """summary_paired.csv as a list of dicts (key, value, reference, group, quantity, n,
        diff_mean, diff_sd, diff_ci95, ref_mean, rel_diff; the quantity's units, rel_diff [-]);
        [] when absent (a study without 2 seeds or more, or not tabulated yet)."""
        return self._table("summary_paired.csv", missing_ok=True)
