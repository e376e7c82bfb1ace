"""The compiled module (_core) when it is built and loads, else a stand-in that says why what
needs the C++ cannot run; the plots, records and reports need only Python."""

import importlib


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
    # By its full name, not `from . import _core`, which would import the package from inside it.
    _core = importlib.import_module(f"{__package__}._core")
    ConfigError, World = _core.ConfigError, _core.World
except ImportError as _error:
    _core = _NoCore("not built" if getattr(_error, "name", None) == f"{__package__}._core"
                    else f"not loadable ({_error})")

    class ConfigError(ValueError):
        """A bad key or value of the damper's settings (the compiled module's, when it is built)."""

    class World:
        """The generic DEM world: C++, in the compiled module."""

        def __new__(cls, *args, **kwargs):
            return _core.World(*args, **kwargs)
