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
import os

import numpy as np

from ._arguments import _count, _out_folder, _sets
from ._native import ConfigError, World, _core  # noqa: F401  (part of the package's interface)
from ._progress import _run
from ._runs import build, calibrate, device, sweep  # noqa: F401
from .study import Study  # noqa: F401

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


def load_config(config=None, settings=None, **kwargs):
    """The damper's settings (with the `vppdem damper` command's defaults) as the C++ reads them."""
    path, sets = _sets(config, settings, kwargs)
    return _core.load_config(path, sets)


# The records write() puts into a folder (and refuses to replace without overwrite=True).
_RECORDS = ("forces.csv", "energy.csv", "cycles.csv", "summary.json")


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
        self._out = _out_folder("out", out) if out is not None else ""
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
        n: a whole number >= 1 (anything else raises ValueError)."""
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

    def write(self, out=None, overwrite=False):
        """forces.csv, energy.csv, cycles.csv and summary.json into `out` (default: the run's folder).
        A folder other than the run's own that holds records already is refused (FileExistsError)
        unless overwrite=True: they would be replaced."""
        out = _out_folder("write(): out", out) if out is not None else self._out
        if not out:
            raise ValueError("write(): no folder: give out here or to Damper(out=...)")
        own = bool(self._out) and os.path.realpath(out) == os.path.realpath(self._out)
        held = [f for f in _RECORDS if os.path.exists(os.path.join(out, f))]
        if held and not own and not overwrite:
            raise FileExistsError(f"write(): {out!r} holds {', '.join(held)} of another run; pass overwrite=True to "
                                  "replace them, or write into another folder")
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
