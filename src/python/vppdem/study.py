"""``vppdem.Study``: a study file (docs/studies.md) and its output folder as one object.

A thin front to what exists: ``run()`` is ``vppdem.sweep``, ``calibrate()`` is
``vppdem.calibrate``, and ``cases()`` and ``report()`` are the command's ``vppdem sweep STUDY
--out DIR --list`` and ``--report-only``, run as a subprocess (the compiled module exposes
neither): the ``vppdem`` binary named by the environment variable ``VPPDEM`` (or
``VPPDEM_BINARY``, as the test suite sets it), else the one of the compiled module's build
(``build/vppdem`` beside ``build/python/vppdem/_core*.so``), else ``vppdem`` on PATH.
``summary()``, ``cases_summary()`` and ``paired()`` read the tables back with the csv module.
Nothing here changes what the engine does or writes.
"""

import csv
import errno
import os
import shutil
import subprocess
import sys
import warnings

from . import ConfigError, _count, _study_sets, calibrate as _calibrate, sweep as _sweep

# Columns that are text whatever they hold (names, messages), never numbers.
_TEXT_COLUMNS = frozenset({"case", "cases", "status", "warnings", "key", "group", "quantity"})

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


def _core_binary():
    """The vppdem binary of the compiled module's build, or None: build/vppdem for
    build/python/vppdem/_core*.so (symbolic links followed), or one beside the module."""
    try:
        from . import _core as core

        module = getattr(core, "__file__", None)
    except ImportError:
        module = None
    if not module:
        return None
    here = os.path.dirname(os.path.realpath(module))
    for d in (os.path.dirname(os.path.dirname(here)), here, os.path.dirname(here)):
        p = os.path.join(d, "vppdem")
        if os.path.isfile(p) and os.access(p, os.X_OK):
            return p
    return None


def find_binary():
    """The path of the ``vppdem`` command that cases() and report() run: $VPPDEM, else
    $VPPDEM_BINARY, else the compiled module's build's, else ``vppdem`` on PATH. Raises
    FileNotFoundError when there is none (or a variable names a file that is not there)."""
    for var in ("VPPDEM", "VPPDEM_BINARY"):
        p = os.environ.get(var, "")
        if p:
            if not (os.path.isfile(p) and os.access(p, os.X_OK)):
                raise FileNotFoundError(errno.ENOENT, f"${var} names no executable vppdem binary", p)
            return p
    p = _core_binary() or shutil.which("vppdem")
    if p is None:
        raise FileNotFoundError("the vppdem binary (for `vppdem sweep --list` / `--report-only`) was not found: "
                                "set VPPDEM=/path/to/build/vppdem, or put vppdem on PATH")
    return p


_checked_builds = set()


def _check_build(binary):
    """Warns once per binary when it is not the compiled module's build (the tables of another
    build may differ: e.g. its stationary-loop criterion)."""
    if binary in _checked_builds:
        return
    _checked_builds.add(binary)
    try:
        from . import _core as core

        mine = dict(core.build())["id"]
    except (ImportError, AttributeError, KeyError):
        return  # no compiled module: nothing to compare with
    try:
        r = subprocess.run([binary, "--version"], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.SubprocessError):
        return
    if r.returncode == 0 and f"build {mine}" not in r.stdout:
        warnings.warn(f"vppdem.Study: {binary} ({r.stdout.strip()}) is not the compiled module's build {mine}; "
                      "set VPPDEM to the binary of the same build", RuntimeWarning, stacklevel=3)


class Study:
    """A study (docs/studies.md) and its output folder.

    ``path``: the study file (TOML); a missing file raises FileNotFoundError naming it.
    ``out``: the folder of the cases and tables (the command's --out; a run into it resumes).
    ``sets`` (["key=value", ...], as --set) and ``settings`` (a dict of dotted keys): fixed
    overrides of every case, as in ``vppdem.sweep`` (a key in both is refused, ValueError).
    ``seeds``: 0 (the study file's own ``seeds``, if any) or N in 1..1000, as --seeds.
    ``publish``: a results folder, as --publish (None: none).

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

    # --- the command, as a subprocess -------------------------------------------------------------
    def _command(self, *flags, quiet=True):
        binary = find_binary()
        _check_build(binary)
        argv = [binary, "sweep", self.path, "--out", self.out, *flags]
        for s in self._extra:
            argv += ["--set", s]
        if self.seeds:
            argv += ["--seeds", str(self.seeds)]
        if quiet and "--report-only" in flags:
            argv.append("--quiet")
        r = subprocess.run(argv, capture_output=True, text=True)
        if not quiet and r.stderr:
            sys.stderr.write(r.stderr)
        if r.returncode != 0:
            why = r.stderr.strip().replace("vppdem: error: ", "") or f"exit status {r.returncode}"
            # Exit status 2: the study or its arguments refused (as vppdem.sweep's ConfigError).
            raise (ConfigError if r.returncode == 2 else RuntimeError)(why)
        return r.stdout

    def cases(self):
        """The study's cases as ``vppdem sweep STUDY --out DIR --list`` gives them (checked, none
        run): a list of dicts in the sweep's order, with ``index`` (1-based, as listed), ``name``
        (the case's folder name), ``folder`` (its path under ``out``), ``group`` (the 1-based
        number of its preparation), ``prepares`` (True: it prepares that sample) and
        ``branches_from`` (the name of the case whose prepared sample it starts from; None when it
        prepares). A bad study raises vppdem.ConfigError with the command's message."""
        rows = []
        for line in self._command("--list").splitlines():
            parts = line.split(None, 4)
            if len(parts) < 5 or parts[1] != "prep":
                continue
            index, _, group, name, rest = parts
            rest = rest.strip()
            prepares = rest == "(prepares)"
            branches = None
            if not prepares:
                if not (rest.startswith("(branches from ") and rest.endswith(")")):
                    raise RuntimeError(f"Study.cases(): cannot read the line {line!r} of `vppdem sweep --list`")
                branches = rest[len("(branches from "):-1]
            rows.append({"index": int(index), "name": name, "folder": os.path.join(self.out, name),
                         "group": int(group), "prepares": prepares, "branches_from": branches})
        return rows

    def report(self, quiet=True):
        """``vppdem sweep STUDY --out DIR --report-only``: runs nothing, and writes summary.csv,
        summary_cases.csv (and, with seeds, summary_paired.csv) from the cases finished in
        ``out``, the others with status "not run" (published too with ``publish``). Returns
        summary() of the new tables. ``out`` must exist (FileNotFoundError naming it).
        quiet=False passes the command's line "N of M cases finished" on to stderr."""
        if not os.path.isdir(self.out):
            raise FileNotFoundError(errno.ENOENT, "Study.report(): no output folder (run() first)", self.out)
        flags = ["--report-only"]
        if self.publish is not None:
            flags += ["--publish", self.publish]
        self._command(*flags, quiet=quiet)
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
        Numbers as floats, empty cells None. FileNotFoundError when absent."""
        return self._table("summary_cases.csv")

    def paired(self):
        """summary_paired.csv as a list of dicts (key, value, reference, group, quantity, n,
        diff_mean, diff_sd, diff_ci95, ref_mean, rel_diff; the quantity's units, rel_diff [-]);
        [] when absent (a study without 2 seeds or more, or not tabulated yet)."""
        return self._table("summary_paired.csv", missing_ok=True)
