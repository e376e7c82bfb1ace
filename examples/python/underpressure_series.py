# W against the underpressure: one prepared sample, one run per dp (the paper's figure 8).
#   PYTHONPATH=build/python /usr/bin/python3 examples/python/underpressure_series.py [OUT]
# The paper's damper at its velocity runs for hours per dp; VPPDEM_SETTINGS (a JSON dict of
# dotted keys, e.g. the tests' small damper) changes any setting.
import json, os, sys
import vppdem

out = sys.argv[1] if len(sys.argv) > 1 else "out/underpressure_py"
os.makedirs(out, exist_ok=True)
settings = json.loads(os.environ.get("VPPDEM_SETTINGS", "{}"))

sample = vppdem.Damper(settings=settings).prepare()
sample.save(f"{out}/prepared.ckpt")  # every dp starts from this sample

with open(f"{out}/series.csv", "w") as f:
    f.write("underpressure,W_last,W_settled\n")
    for dp in [0.02e6, 0.04e6, 0.06e6, 0.08e6]:  # [Pa]
        # merged into settings: a keyword giving a key that settings give too is refused
        d = vppdem.Damper.load(f"{out}/prepared.ckpt", settings={**settings, "process.underpressure": dp}).run()
        s = d.summary()
        f.write(f"{dp},{d.W[-1]},{s['W_settled']}\n")
        print(f"dp = {dp / 1e6:.2f} MPa: W = {d.W[-1]:.4g} J/m^2 (last cycle)")
