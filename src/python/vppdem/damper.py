"""vppdem.Damper: the VPP damper run one stage at a time from Python (the `vppdem damper`
command's stages, the same C++ underneath)."""

import json
import os

import numpy as np

from ._arguments import _count, _out_folder, _sets
from ._native import _core
from ._progress import _run


def load_config(config=None, settings=None, **kwargs):
    """The damper's settings (with the `vppdem damper` command's defaults) as the C++ reads them."""
    path, sets = _sets(config, settings, kwargs)
    return _core.load_config(path, sets)


def _whole(columns, names):
    """The named columns of a {name: array} record as integer arrays (counts and indices the
    engine holds as doubles)."""
    for n in names:
        if n in columns:
            columns[n] = np.asarray(columns[n]).astype(np.int64)
    return columns


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
        force_lid, force_machine_zeroed [N]; cycle as integers. Each column's unit and meaning:
        ``vppdem.record_columns()``."""
        return _whole(self._d.forces(), ("cycle",))

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
        return self.forces()["cycle"]

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
        output.energy = false), settled (1/0); cycle and settled as integers. Each column's unit and
        meaning: ``vppdem.record_columns()``."""
        return _whole(self._d.cycles(), ("cycle", "settled"))

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
        """[m] particle radii, in the order of ``positions``."""
        return self._d.radii()
