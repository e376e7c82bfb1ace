"""vppdem from Python: the VPP damper's stages, the generic DEM world, sweeps and calibrations.

The same C++ as the ``vppdem`` command runs underneath, so a damper run from here writes the
same forces.csv as ``vppdem damper`` with the same settings, seed and thread count.

Settings are the damper config's dotted keys (docs/config.md), given three ways:
  * ``config``: a TOML file's path, or a dict (nested tables or dotted keys): the base, which
    the other two override, as ``--set`` overrides the command's config file;
  * ``settings``: a dict of dotted keys, e.g. ``{"process.underpressure": 0.06e6}``;
  * keyword arguments, with ``__`` for the dot: ``process__underpressure=0.06e6`` (or
    ``**{"process.underpressure": 0.06e6}``).
A key given twice among ``settings`` and the keywords (or twice within one of them, as a
nested table and a dotted key) with two different values is refused (ValueError naming the key
and both values): neither is more deliberate than the other. To override a dict's value, merge
it first: ``settings={**base, "process.underpressure": dp}``.
A bad key or value raises ``vppdem.ConfigError`` (a ValueError) with the command's message.

Plots of output folders (no compiled module needed): ``vppdem.plot.damper(dir)``, ``.sweep(dir)``,
``.calibration(dir)``, or ``python3 -m vppdem.plot DIR``; CSV records: ``vppdem.records``; the
studies' reports (docs/ pages) and their statistics: ``vppdem.report`` (``python3 -m vppdem.report``).
Without the compiled module (``_core``, e.g. PYTHONPATH=src/python), ``import vppdem`` still
works for those; what runs the C++ (Damper, World, load_config, settings, sweep, calibrate)
raises ImportError.

Stepping releases the interpreter lock; Ctrl-C stops a run with KeyboardInterrupt (checked every
256 steps): a cycle stopped part way is left out of W, cycles() and the records (summary.json's
warnings name it, forces.csv keeps its samples) until ``cycle()`` finishes it. One Damper takes
one call at a time: while a stage, save() or write() runs, a call on it from another thread
raises RuntimeError (the progress callback, on the running thread, may read it). ``progress``: None (quiet), True (a tqdm bar when tqdm is installed, else a line on
stderr now and then), or a callable ``f(stage, done, total, time)``.
"""

import importlib
import json
import math
import os
import sys

import numpy as np


class _NoCore:
    """Stands in for the compiled module when it is not built or does not load: the plots and
    records need only Python, and what needs the C++ says why it cannot run."""

    def __init__(self, why):
        self.why = why

    def __getattr__(self, name):
        if name.startswith("__"):  # probes such as hasattr(module, "__file__") expect AttributeError
            raise AttributeError(name)
        raise ImportError(f"vppdem's compiled module _core is {self.why}: configure with -DVPPDEM_PYTHON=ON "
                          "(pybind11 and Python 3 found), build, and put build/python on PYTHONPATH")


try:
    from ._core import ConfigError, World  # noqa: F401  (part of the package's interface)
    from . import _core
except ImportError as _error:
    _core = _NoCore("not built" if getattr(_error, "name", None) == f"{__name__}._core"
                    else f"not loadable ({_error})")

    class ConfigError(ValueError):
        """A bad key or value of the damper's settings (the compiled module's, when it is built)."""

    class World:
        """The generic DEM world: C++, in the compiled module."""

        def __new__(cls, *args, **kwargs):
            return _core.World(*args, **kwargs)


__all__ = ["Damper", "World", "ConfigError", "load_config", "settings", "record_columns", "sweep", "calibrate", "device",
           "build", "Study"]


def __getattr__(name):
    # vppdem.plot (matplotlib), vppdem.records and vppdem.report, imported when first named, so
    # that `import vppdem` stays as quick as before.
    if name in ("plot", "records", "report"):
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'vppdem' has no attribute '{name}'")


def settings(command="damper"):
    """The settings table of ``command`` as a list of dicts (key, type, unit, default, allowed,
    doc, ...): "damper" (the keys of Damper, sweep and calibrate; docs/config.md, "VPP commands")
    or "scene" (the keys of a ``vppdem scene`` file; a key of an array of tables reads
    ``spheres[].radius``, default None when required). The same tables the readers use."""
    if command == "damper":
        return _core.damper_settings()
    if command == "scene":
        return _core.scene_settings()
    raise ValueError(f"settings: command = {command!r}: must be \"damper\" or \"scene\"")


def record_columns():
    """The columns of the damper's records as a list of dicts (record "cycles" or "forces", name,
    unit, meaning, only_with): what ``Damper.cycles()`` and ``Damper.forces()`` return, cycles.csv
    and forces.csv hold and summary.json's "cycles" lists. The same table the C++ writers use."""
    return _core.record_columns()


def _literal(key, v):
    """A Python value as the TOML literal `--set key=value` takes."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)  # shortest text that reads back to the same double
    if isinstance(v, str):
        return json.dumps(v)  # a TOML basic string
    raise ConfigError(f"config key '{key}': cannot use a value of type {type(v).__name__} ({v!r})")


def _same_value(a, b):
    """Whether two values of one key say the same: equal numbers (2 and 2.0), or the same
    literal (True is not 1 here: the readers tell a boolean from an integer)."""
    if isinstance(a, bool) or isinstance(b, bool):
        return isinstance(a, bool) and isinstance(b, bool) and a == b
    if isinstance(a, (int, float, np.integer, np.floating)) and isinstance(b, (int, float, np.integer, np.floating)):
        return a == b or (math.isnan(a) and math.isnan(b))
    try:
        return type(a) is type(b) and bool(a == b)
    except (TypeError, ValueError):  # e.g. arrays (which no key takes): not the same
        return False


def _put(out, key, v, where, first):
    """out[key] = v, refusing a second, different value of the key (`where` names the source of
    v, `first` that of the value already there)."""
    if key in out and not _same_value(out[key], v):
        raise ValueError(f"config key '{key}' given twice with different values: {out[key]!r} ({first[key]}) and "
                         f"{v!r} ({where}); give it once (to override a dict's value, merge it first: "
                         f"settings={{**base, '{key}': value}})")
    if key not in out:
        out[key] = v
        first[key] = where


def _flatten(d, prefix="", where="settings", out=None, first=None):
    """A dict of nested tables and dotted keys as {dotted key: value}; the same key twice (a
    nested table and a dotted key) is refused unless the values agree."""
    out = {} if out is None else out
    first = {} if first is None else first
    for k, v in d.items():
        key = f"{prefix}.{k}" if prefix else str(k)
        if isinstance(v, dict):
            _flatten(v, key, where, out, first)
        else:
            _put(out, key, v, where, first)
    return out


def _dict_argument(name, d):
    """The settings dict `name`, or a TypeError naming what it is instead (a list of pairs or of
    "key=value" strings used to fail with AttributeError: 'list' object has no attribute 'items')."""
    if d is None:
        return {}
    if not isinstance(d, dict):
        raise TypeError(f"{name}: a dict of dotted keys, e.g. {{\"process.underpressure\": 0.06e6}}, not "
                        f"{type(d).__name__} ({d!r:.80})")
    return d


def _sets(config, settings, kwargs):
    """(path of the TOML file or "", the key=value overrides in order). `config` (a file or a
    dict) is the base; `settings` and the keywords override it, and may not disagree with each
    other (a keyword used to beat the same key in `settings` without a word)."""
    path, base = "", {}
    if config is None:
        pass
    elif isinstance(config, (str, os.PathLike)):
        path = os.fspath(config)
    elif isinstance(config, dict):
        base = _flatten(config, where="config")
    else:
        raise TypeError(f"config: a TOML file's path or a dict, not {type(config).__name__}")
    values, first = {}, {}
    _flatten(_dict_argument("settings", settings), out=values, first=first)
    for k, v in kwargs.items():
        _put(values, k.replace("__", "."), v, f"keyword {k}", first)
    base.update(values)
    return path, [f"{k}={_literal(k, v)}" for k, v in base.items()]


def load_config(config=None, settings=None, **kwargs):
    """The damper's settings (with the `vppdem damper` command's defaults) as the C++ reads them."""
    path, sets = _sets(config, settings, kwargs)
    return _core.load_config(path, sets)


class _Bar:
    """What both progress callbacks share: the user's callable, or a tqdm bar when tqdm is
    installed and progress is True (else lines on stderr)."""

    def __init__(self, progress):
        self.user = progress if callable(progress) else None
        self.bar = None
        self.tqdm = None
        if progress is True:
            try:
                from tqdm import tqdm

                self.tqdm = tqdm
            except ImportError:
                pass

    def close(self):
        if self.bar is not None:
            self.bar.close()
            self.bar = None


class _Progress(_Bar):
    """The callback handed to the C++ stages (called every 256 steps, with the lock held)."""

    def __init__(self, progress):
        super().__init__(progress)
        self.stage = None
        self.last = 0.0

    def __call__(self, stage, done, total, time):
        if self.user is not None:
            self.user(stage, done, total, time)
            return
        if self.tqdm is not None:
            if stage != self.stage:
                self.close()
                self.bar = self.tqdm(total=total, desc=stage, unit="step")
                self.stage = stage
            self.bar.n = min(done, total)
            self.bar.refresh()
            return
        import time as _t

        now = _t.monotonic()
        if now - self.last > 2.0 or stage != self.stage:
            self.last, self.stage = now, stage
            print(f"[{stage}] {100.0 * done / max(total, 1):5.1f}%  t = {time:.6g} s", file=sys.stderr)


class _CaseProgress(_Bar):
    """The callback of a sweep or calibration: (done, total, case) after each finished case,
    called from the study's threads with the lock held."""

    def __call__(self, done, total, case):
        if self.user is not None:
            self.user(done, total, case)
            return
        if self.tqdm is not None:
            if self.bar is None:
                self.bar = self.tqdm(total=total, desc="cases", unit="case")
            self.bar.n = min(done, total)
            self.bar.set_postfix_str(case)
            return
        print(f"[{done}/{total}] {case}", file=sys.stderr)


def _count(name, v, low, high=None, also=""):
    """v as an int, refusing a bool, a non-integer (1.5; int() would cut it) and a value outside
    [low, high], with a message naming `name`, v and what is allowed (`also`: what else is)."""
    import operator

    allowed = f"a whole number >= {low}" + ("" if high is None else f" and <= {high}") + also
    if isinstance(v, bool):
        raise TypeError(f"{name} = {v!r}: {allowed}, not a bool")
    try:
        i = operator.index(v)
    except TypeError:
        if isinstance(v, (float, np.floating)) and math.isfinite(v) and float(v).is_integer():
            i = int(v)  # 3.0 is three
        else:
            raise (ValueError if isinstance(v, (float, np.floating)) else TypeError)(
                f"{name} = {v!r}: {allowed}") from None
    if i < low or (high is not None and i > high):
        raise ValueError(f"{name} = {i}: {allowed}")
    return i


def _run(call, progress, *args, callback=_Progress, **kwargs):
    """call(*args, hook, **kwargs): hook a `callback` made from progress (None when progress is
    None or False), closed (its bar) however the call ends."""
    hook = None if progress is None or progress is False else callback(progress)
    try:
        return call(*args, hook, **kwargs)
    finally:
        if hook is not None:
            hook.close()


class Damper:
    """The VPP damper run one stage at a time (the `vppdem damper` command's stages).

    ``out``: a folder for the run's files as the command writes them (checkpoints, VTK frames,
    prepared.ckpt; ``write()`` adds the records); None writes nothing. The object holds the
    folder's lock until it is deleted: another run into it, in another process or in this one,
    is refused (docs/damper.md, "One run per folder"), so a new Damper for the same folder needs
    the old one deleted first (``del d``). ``quiet=False`` prints the command's log on stderr.
    """

    def __init__(self, config=None, settings=None, *, out=None, overwrite=False, quiet=True, _from="", **kwargs):
        self._config = load_config(config, settings, **kwargs)
        self._from = os.fspath(_from) if _from else ""
        self._out = os.fspath(out) if out is not None else ""
        self._d = _core.Damper(self._config, self._out, self._from, overwrite, quiet)

    @classmethod
    def load(cls, path, config=None, settings=None, *, out=None, overwrite=False, quiet=True, **kwargs):
        """Continues from a checkpoint (save(), prepared.ckpt or run.ckpt): its geometry and, for a
        run that started, its settings replace the given ones (a conflicting value is an error)."""
        return cls(config, settings, out=out, overwrite=overwrite, quiet=quiet, _from=path, **kwargs)

    # --- stages ---------------------------------------------------------------------------------
    def prepare(self, progress=None):
        """Fill the foil and compress the grains to the damper height (the prepared sample)."""
        _run(self._d.prepare, progress)
        return self

    def vacuum(self, progress=None):
        """Ramp the underpressure up and bring the sample to rest (prepares first if needed)."""
        _run(self._d.vacuum, progress)
        return self

    def cycle(self, n=None, progress=None):
        """Run n more cycles (None: all of process.cycles that remain); returns the cycles done.
        n is a whole number >= 1: cycle(-5) used to run all the cycles that remain, and
        int() turned 1.5 into 1."""
        return _run(self._d.cycle, progress, -1 if n is None else _count("cycle(): n", n, 1, 2**31 - 1,
                                                                       ", or None for all that remain"))

    def run(self, progress=None):
        """All stages: prepare, vacuum, every cycle."""
        self.prepare(progress)
        self.vacuum(progress)
        self.cycle(None, progress)
        return self

    def save(self, path):
        """A checkpoint Damper.load(path) continues from (bit for bit)."""
        self._d.save(os.fspath(path))

    def write(self, out=None):
        """forces.csv, energy.csv, cycles.csv and summary.json into `out` (default: the run's folder)."""
        out = os.fspath(out) if out is not None else self._out
        if not out:
            raise ValueError("write(): no folder: give out here or to Damper(out=...)")
        # Before the sample is prepared there is nothing to record: the files would be empty
        # records that look like a run's (forces.csv with a header only, summary.json without a
        # preparation).
        stage = self.stage
        if stage in ("fill", "compress"):
            raise RuntimeError(f"write(): nothing to write: the damper is at stage '{stage}', before its sample is "
                               "prepared; run prepare(), vacuum(), cycle() or run() first")
        os.makedirs(out, exist_ok=True)
        self._d.write(out, self._from)

    # --- state and records ------------------------------------------------------------------------
    @property
    def stage(self):
        """'fill', 'compress', 'prepared', 'vacuum', 'cycle' or 'done'."""
        return self._d.stage()

    @property
    def cycles_done(self):
        """The cycles finished (a cycle stopped part way, by Ctrl-C, does not count)."""
        return self._d.cycles_done()

    @property
    def incomplete_cycle(self):
        """The cycle stopped part way (Ctrl-C; a checkpoint written mid-cycle), whose samples are
        in forces() but which W, cycles() and the records leave out; None when there is none."""
        c = self.forces()["cycle"]
        last = int(c[-1]) if c.shape[0] else 0
        return last if last > self.cycles_done else None

    @property
    def time(self):
        """[s] simulated time."""
        return self._d.time()

    def _samples(self):
        return self._d.samples()

    @property
    def sample_time(self):
        """[s] simulated time of each sample, counted from the start of the simulation (the
        preparation's start); ``time`` counts from the start of cycling, as forces.csv does."""
        return self._samples()[:, 0]

    @property
    def displacement(self):
        """[m] cap travel from the cycling start position per sample, compression positive."""
        return self._samples()[:, 1]

    @property
    def force_grains(self):
        """[N] grains on the upper cap per sample (averaged over process.sample_window)."""
        return self._samples()[:, 2]

    @property
    def force_foil(self):
        """[N] foil on the top ring per sample."""
        return self._samples()[:, 3]

    def forces(self):
        """forces.csv's columns as arrays, from the rows the file is written from: time [s] since
        the start of cycling, displacement [m], force_total, force_grains, force_foil,
        force_zeroed [N], cycle, and with the air record (process.pressure_model = "pump" or
        output.air) enclosed_volume, gas_volume [m^3], pressure_inside, underpressure [Pa],
        force_lid, force_machine_zeroed [N]. Each column's unit and meaning:
        ``vppdem.record_columns()``."""
        return self._d.forces()

    @property
    def time(self):
        """[s] time of each sample since the start of cycling (forces.csv time)."""
        return self.forces()["time"]

    @property
    def force_total(self):
        """[N] grains + foil per sample (forces.csv force_total)."""
        return self.forces()["force_total"]

    @property
    def force_zeroed(self):
        """[N] force_total minus its first sample's (forces.csv force_zeroed; the loops' force)."""
        return self.forces()["force_zeroed"]

    @property
    def cycle_index(self):
        """1-based cycle of each sample (forces.csv cycle)."""
        return self.forces()["cycle"].astype(int)

    def air(self):
        """The air inside at each sample (process.pressure_model = "pump" or output.air; forces.csv's
        air columns): enclosed_volume and gas_volume [m^3], pressure_inside and underpressure [Pa],
        force_lid [N] (-dp times the lid's area), gas_work [J]. Empty arrays when not recorded."""
        a = self._d.air()
        return {"enclosed_volume": a[:, 0], "gas_volume": a[:, 1], "pressure_inside": a[:, 2],
                "underpressure": a[:, 3], "force_lid": -a[:, 3] * a[:, 4], "gas_work": a[:, 5]}

    def _config_value(self, key):
        return self.summary()["inputs"][key]

    def cycles(self):
        """Per cycle, as arrays, the columns of cycles.csv and summary.json's "cycles": cycle,
        dissipated_energy [J], W [J/m^2], peak_force and min_force [N], the ledger's
        boundary_work, friction/damping/viscous_dissipation and energy_residual [J] (NaN with
        output.energy = false), settled (1/0). Each column's unit and meaning:
        ``vppdem.record_columns()``."""
        return self._d.cycles()

    @property
    def W(self):
        """[J/m^2] W of each cycle."""
        return self.cycles()["W"]

    def energy(self):
        """The energy ledger at each sample (energy.csv): column name -> array ([s], then [J])."""
        e = self._d.energy()
        cols = _core.Damper.energy_columns()
        if e.shape[0] == 0:
            return {c: np.zeros(0) for c in cols}
        return {c: e[:, k] for k, c in enumerate(cols)}

    def summary(self):
        """summary.json as a dict (what write() would write)."""
        return json.loads(self._d.summary_json(self._from))

    @property
    def positions(self):
        """[m] (n, 3) particle positions: foil first, then grains."""
        return self._d.positions()

    @property
    def radii(self):
        return self._d.radii()


def _study_sets(sets, settings):
    """The fixed overrides of a study: `sets` ("key=value" strings, as --set) and `settings` (a
    dict); a key in both is refused (which one would win is not what either says)."""
    if sets is None:
        sets = []
    if not isinstance(sets, (str, bytes, dict)):
        sets = list(sets)
    if isinstance(sets, (str, bytes, dict)) or not all(isinstance(s, str) for s in sets):
        raise TypeError(f"sets: a list of \"key=value\" strings, as --set takes, not {sets!r:.80}")
    extra = _sets(None, settings, {})[1]
    given = {s.split("=", 1)[0].strip() for s in sets}
    for s in extra:
        key = s.split("=", 1)[0]
        if key in given:
            raise ValueError(f"config key '{key}' given both in sets and in settings; give it once")
    return list(sets) + extra


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
    return _run(_core.sweep, progress, os.fspath(study_path), os.fspath(out), extra, int(seeds),
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
    written."""
    extra = _study_sets(sets, settings)
    if not float(checkpoint_every) > 0.0 or not math.isfinite(float(checkpoint_every)):
        raise ValueError(f"checkpoint_every = {checkpoint_every!r}: must be a finite number of seconds > 0")
    return _core.device(os.fspath(device_file), os.fspath(out), extra,
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
    rc = _run(_core.calibrate, progress, os.fspath(study_path), os.fspath(experiment), os.fspath(out), extra,
              int(seeds), _count("jobs", jobs, 0, 2**31 - 1), bool(quiet), 1e-3 if displacement_unit == "mm" else 1.0,
              1e3 if force_unit == "kN" else 1.0, bool(compression_negative), simulated_force,
              int(points), bool(plot), time_column, displacement_column, force_column, callback=_CaseProgress,
              mix_builds=bool(mix_builds))
    path = os.path.join(os.fspath(out), "calibration.json")
    if rc != 0 or not os.path.exists(path):
        raise RuntimeError(f"calibrate: no calibration (exit status {rc}); see {out}")
    with open(path) as f:
        return json.load(f)


# vppdem.Study: a study file and its output folder as one object (src/python/vppdem/study.py); at the
# end, as it uses sweep() and calibrate() above.
from .study import Study  # noqa: E402
