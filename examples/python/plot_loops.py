# %% [markdown]
# Force-displacement loops of a damper run, split into grains and foil: the run from Python, its
# records written, and the plots of `vppdem plot` drawn by the package's vppdem.plot.
#   PYTHONPATH=build/python /usr/bin/python3 examples/python/plot_loops.py [OUT]
# Cells (# %%) run one by one in an editor that knows them. VPPDEM_SETTINGS (JSON) changes
# settings, e.g. the tests' small damper for a quick look.

# %%
import json
import os
import sys

import vppdem
import vppdem.plot

out = sys.argv[1] if len(sys.argv) > 1 else "out/loops_py"
os.makedirs(out, exist_ok=True)
settings = json.loads(os.environ.get("VPPDEM_SETTINGS", "{}"))

# %% The run, with a progress bar (tqdm when installed); its records (forces.csv, cycles.csv,
# energy.csv, summary.json) into OUT, replacing an earlier run's
d = vppdem.Damper(settings=settings, out=out, overwrite=True)
d.run(progress=True)
d.write()

# %% The loops (total, foil on the top ring, grains on the cap; one colour per cycle, W in the
# legend) and where the energy goes, as `vppdem plot OUT` draws them
for path in vppdem.plot.damper(out):
    print(f"wrote {path}")

# %% W and the dissipation split per cycle (energy ledger)
c = d.cycles()
for k in range(len(c["W"])):
    print(f"cycle {int(c['cycle'][k])}: W = {c['W'][k]:.4g} J/m^2, friction {c['friction_dissipation'][k]:.3g} J, "
          f"damping {c['damping_dissipation'][k]:.3g} J, viscous {c['viscous_dissipation'][k]:.3g} J")
