# %% [markdown]
# Force-displacement loops of a damper run, split into grains and foil, with matplotlib.
#   PYTHONPATH=build/python /usr/bin/python3 examples/python/plot_loops.py [OUT]
# Cells (# %%) run one by one in an editor that knows them. VPPDEM_SETTINGS (JSON) changes
# settings, e.g. the tests' small damper for a quick look.

# %%
import json
import os
import sys

import matplotlib

if not os.environ.get("DISPLAY"):
    matplotlib.use("Agg")  # no screen: write the PNG only
import matplotlib.pyplot as plt

import vppdem

out = sys.argv[1] if len(sys.argv) > 1 else "out/loops_py"
os.makedirs(out, exist_ok=True)
settings = json.loads(os.environ.get("VPPDEM_SETTINGS", "{}"))

# %% The run, with a progress bar (tqdm when installed)
d = vppdem.Damper(settings=settings)
d.run(progress=True)

# %% The loops: total force, the grains' share on the cap, the foil's on the top ring
mm = 1e3 * d.displacement  # [mm]
fig, ax = plt.subplots(1, 3, figsize=(13, 4), sharex=True)
for a, (name, f) in zip(ax, [("total", d.force_total), ("grains", d.force_grains), ("foil", d.force_foil)]):
    for c in sorted(set(d.cycle_index)):
        k = d.cycle_index == c
        a.plot(mm[k], f[k], lw=1, label=f"cycle {c}")
    a.set(title=name, xlabel="displacement [mm]", ylabel="force [N]")
ax[0].legend()
fig.tight_layout()
fig.savefig(f"{out}/loops.png", dpi=120)

# %% W and the dissipation split per cycle (energy ledger)
c = d.cycles()
for k in range(len(c["W"])):
    print(f"cycle {int(c['cycle'][k])}: W = {c['W'][k]:.4g} J/m^2, friction {c['friction_dissipation'][k]:.3g} J, "
          f"damping {c['damping_dissipation'][k]:.3g} J, viscous {c['viscous_dissipation'][k]:.3g} J")
print(f"wrote {out}/loops.png")
