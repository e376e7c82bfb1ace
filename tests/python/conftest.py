# Shared settings of the Python tests: the small, quick damper of the C++ tests
# (tests/physics/cli_helpers.h: 56 grains, 494 foil particles, 2 mm cycles at 0.1 m/s).
import os

import pytest

import vppdem

SMALL = {
    "damper.radius": 0.012,           # [m]
    "damper.height": 0.03,            # [m]
    "grains.volume_fraction": 0.45,   # [-]
    "process.velocity": 0.1,          # [m/s]
    "process.amplitude": 0.002,       # [m]
    "process.cycles": 2,
    "process.samples_per_cycle": 80,
    "simulation.threads": 1,
    "simulation.dt_safety": 0.45,     # [-] the C++ tests' step (tests/physics/cli_helpers.h): features, not convergence
    # Mass-scaled as the C++ feature tests' damper (cli_helpers.h, kSmallDamper): densities 100
    # times the paper's, the step 10 times longer, a run about 5 times quicker.
    "grains.density": 268963.9,       # [kg/m^3]
    "foil.density": 15177,            # [kg/m^3]
}

# The mass scaling alone, as --set arguments: for the tests that run a study file's own [set]
# (their question is the records and the branching, not the grains' inertia).
MASS_SCALED = [f"{k}={SMALL[k]}" for k in ("grains.density", "foil.density")]

# The same as the command's --set arguments.
# A tiny study: the small damper (mass-scaled), two frictions sharing one preparation, one cycle
# each (seconds of CPU; test_studies.py, test_study_class.py).
TINY_STUDY = """
[set]
"damper.radius" = 0.012
"damper.height" = 0.03
"grains.volume_fraction" = 0.45
"process.velocity" = 0.1
"process.amplitude" = 0.002
"process.cycles" = 1
"process.samples_per_cycle" = 40
"simulation.threads" = 1
"simulation.dt_safety" = 0.45
"grains.density" = 268963.9
"foil.density" = 15177

[grid]
"grains.friction" = [0.3, 0.6]
"""

SMALL_SETS = " ".join(f"--set {k}={v}" for k, v in SMALL.items())

BINARY = os.environ.get("VPPDEM_BINARY", "")
SOURCE_DIR = os.environ.get("VPPDEM_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(__file__))))


@pytest.fixture(scope="session")
def vacuumed(tmp_path_factory):
    """The small damper after the vacuum, saved (tests load it rather than preparing again)."""
    d = vppdem.Damper(settings=SMALL)
    d.vacuum()
    path = tmp_path_factory.mktemp("vacuumed") / "vacuumed.ckpt"
    d.save(path)
    return path


@pytest.fixture(scope="session")
def finished(vacuumed):
    """The small damper cycled to the end (both cycles in one call)."""
    d = vppdem.Damper.load(vacuumed, settings=SMALL)
    d.cycle()
    return d


def flat_keys(table, prefix=""):
    """A TOML table as dotted keys ("process.velocity" quoted or as nested tables alike)."""
    out = {}
    for k, v in table.items():
        if isinstance(v, dict):
            out.update(flat_keys(v, prefix + k + "."))
        else:
            out[prefix + k] = v
    return out


def read_study(path):
    """A study file: its top-level table, its [set] and its [grid] as dotted keys."""
    import tomllib
    with open(path, "rb") as f:
        s = tomllib.load(f)
    return s, flat_keys(s.get("set", {})), flat_keys(s.get("grid", {}))
