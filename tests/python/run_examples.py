# ctest python_examples: every script in examples/python runs, shortened: the damper scripts on
# the tests' small damper for one cycle, the scene for a few hundred steps.
#   run_examples.py SCRATCH_DIR
import json
import os
import shutil
import subprocess
import sys

from conftest import SMALL, SOURCE_DIR

scratch = sys.argv[1]
shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)
env = dict(os.environ, MPLBACKEND="Agg", VPPDEM_SCENE_STEPS="400",
           VPPDEM_SETTINGS=json.dumps(dict(SMALL, **{"process.cycles": 1, "process.samples_per_cycle": 40})))
examples = os.path.join(SOURCE_DIR, "examples", "python")
names = sorted(n for n in os.listdir(examples) if n.endswith(".py"))
assert names, "no examples"
for n in names:
    out = os.path.join(scratch, n[:-3])
    r = subprocess.run([sys.executable, os.path.join(examples, n), out], env=env, capture_output=True, text=True)
    print(f"--- {n}: exit {r.returncode}\n{r.stdout}{r.stderr}")
    if r.returncode != 0:
        sys.exit(f"example {n} failed")
shutil.rmtree(scratch)
