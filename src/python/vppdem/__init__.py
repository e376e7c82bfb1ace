"""vppdem from Python: the VPP damper's stages, the generic DEM world, sweeps and calibrations.

The same C++ as the ``vppdem`` command runs underneath: a damper run from here writes the same
forces.csv as ``vppdem damper`` with the same settings, seed and thread count.

What is here (each has its own help, e.g. ``help(vppdem.Damper)``):
  Damper(config, settings, out=..., **keys)  the damper run one stage at a time: prepare(),
                                    vacuum(), cycle(n), run(); forces(), cycles(), energy(), W,
                                    summary(), write(out), save(path), Damper.load(path)
  sweep(study, out, ...)            a parameter study (``vppdem sweep``); returns the failed count
  calibrate(study, experiment, out, ...)  a grid search against a measured loop
  Study(study, out)                 a study's cases, run() and summary() as rows
  device(file, out, ...)            a gripper or beam device run (``vppdem device``)
  World()                           the generic DEM world: materials, spheres, walls, step(n)
  load_config(...), settings(), record_columns()   the settings and the records' columns
  ConfigError                       a bad key or value (a ValueError with the command's message)
  vppdem.plot, vppdem.records, vppdem.report   plots, CSV records and the studies' reports
                                    (these need no compiled module)

Settings are the damper config's dotted keys (docs/config.md), given three ways:
  * ``config``: a TOML file's path, or a dict (nested tables or dotted keys): the base, which
    the other two override, as ``--set`` overrides the command's config file;
  * ``settings``: a dict of dotted keys, e.g. ``{"process.underpressure": 0.06e6}``;
  * keyword arguments, with ``__`` for the dot: ``process__underpressure=0.06e6``.
A key given twice with two different values is refused (ValueError naming the key and both
values); to override a dict's value, merge it first: ``settings={**base, "process.underpressure": dp}``.

``progress``: None (quiet), True (a line per stage with the rate and the time left, or a tqdm
bar when tqdm is installed), or a callable ``f(stage, done, total, time)``. Stepping releases the
interpreter lock; Ctrl-C stops a run with KeyboardInterrupt (a cycle stopped part way is left
out of W and the records until ``cycle()`` finishes it). Without the compiled module (``_core``,
e.g. PYTHONPATH=src/python) ``import vppdem`` still works for plot, records and report; what
runs the C++ raises ImportError. The whole guide: docs/python.md.
"""

import importlib as _importlib

from ._native import ConfigError, World, _core  # noqa: F401  (part of the package's interface)
from ._runs import build, calibrate, device, sweep  # noqa: F401
from .damper import Damper, load_config  # noqa: F401
from .study import Study  # noqa: F401

# No __all__: help(vppdem) then shows this page and the functions defined here, not every class
# in full (help(vppdem.Damper) does); the public names are those without a leading underscore.


def __getattr__(name):
    """vppdem.plot (matplotlib), vppdem.records and vppdem.report, imported when first named (so
    that ``import vppdem`` stays quick)."""
    if name in ("plot", "records", "report"):
        return _importlib.import_module(f".{name}", __name__)
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
