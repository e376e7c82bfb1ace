# ctest python_matches_cli: the small damper run from Python (vppdem.Damper, its stages one call
# at a time) and from the command (`vppdem damper`) with the same settings, seed and thread count
# write the same forces.csv, energy.csv and cycles.csv, byte for byte.
#   compare_cli.py VPPDEM_BINARY SCRATCH_DIR
import filecmp
import os
import shutil
import subprocess
import sys

import vppdem
from conftest import SMALL, SMALL_SETS

binary, scratch = sys.argv[1], sys.argv[2]
shutil.rmtree(scratch, ignore_errors=True)
cli_out, py_out = os.path.join(scratch, "cli"), os.path.join(scratch, "python")
subprocess.run(f"{binary} damper --out {cli_out} {SMALL_SETS} --no-plot --quiet", shell=True, check=True)

d = vppdem.Damper(settings=SMALL, out=py_out)
d.prepare()
d.vacuum()
d.cycle(1)  # the cycles in two calls: the same run as one
d.cycle()
d.write()

bad = [f for f in ("forces.csv", "energy.csv", "cycles.csv")
       if not filecmp.cmp(os.path.join(cli_out, f), os.path.join(py_out, f), shallow=False)]
if bad:
    sys.exit(f"python and command differ in {', '.join(bad)} ({cli_out} vs {py_out})")
rows = sum(1 for _ in open(os.path.join(py_out, "forces.csv"))) - 1
print(f"forces.csv, energy.csv, cycles.csv identical ({rows} samples, W = {list(d.W)})")
shutil.rmtree(scratch)
