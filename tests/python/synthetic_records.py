# Synthetic run records for the reports' tests (test_report_*.py): hand-made case folders with the
# records a finished run publishes (cycles.csv, summary.json), written with the text the C++ tests
# wrote (tests/physics/test_tools.cpp before issue 59: std::to_string's six decimals), and the
# reports run on them in this process (python3 -m vppdem.report NAME, scripts/paper_report.sh's
# steps) with their exit status and everything they printed.
import contextlib
import csv
import io
import os
import shutil
import subprocess
import sys
import tempfile

from conftest import BINARY, SOURCE_DIR

# cycles.csv's columns as a published run has them (the energy ledger's are the damping study's).
CYCLES = "cycle,dissipated_energy,W,peak_force,min_force"
LEDGER = "friction_dissipation,damping_dissipation,viscous_dissipation,settled"
SUMMARY = '{"run_seconds": 1, "grains": 1090}\n'


def num(x):
    """A number as C++'s std::to_string writes it: an int as such, a float with six decimals."""
    return str(x) if isinstance(x, int) else f"{x:f}"


def write_file(path, text):
    os.makedirs(os.path.dirname(str(path)), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def read(path):
    with open(path) as f:
        return f.read()


def rows_of(path):
    """A CSV's rows as dicts from column name to text."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def write_cycles(case, W, energy=1, extra=None):
    """case/cycles.csv: cycle k (from 1) at W[k-1], dissipated energy `energy` (one number for every
    cycle, or one per cycle), peak force 100 N, min force 0; `extra`: per cycle, the ledger's values
    (friction, damping, viscous dissipation, settled), which add its columns."""
    energies = energy if isinstance(energy, (list, tuple)) else [energy] * len(W)
    lines = [CYCLES + ("," + LEDGER if extra else "")]
    for k, (w, e) in enumerate(zip(W, energies)):
        row = [str(k + 1), num(e), num(w), "100", "0"] + ([num(v) for v in extra[k]] if extra else [])
        lines.append(",".join(row))
    write_file(os.path.join(case, "cycles.csv"), "\n".join(lines) + "\n")


def summary_json(grains=1090, packing=None, warnings=None):
    """A run's summary.json as the paper report reads it (run_seconds, grains, the preparation's
    packing fraction, the run's warnings)."""
    s = f'{{"run_seconds": 1, "grains": {grains}'
    if packing is not None:
        s += f', "preparation": {{"packing_fraction": {num(float(packing))}}}'
    if warnings is not None:
        s += ', "warnings": [' + ", ".join(f'"{w}"' for w in warnings) + "]"
    return s + "}\n"


def write_run(case, W, energy=1, extra=None, **summary):
    """A finished run: case/cycles.csv (write_cycles) and case/summary.json (summary_json)."""
    write_cycles(case, W, energy, extra)
    write_file(os.path.join(case, "summary.json"), summary_json(**summary))


def run_report(name, *args):
    """`python3 -m vppdem.report NAME ARGS...` in this process: (exit status, stdout and stderr)."""
    from vppdem.report import __main__ as entry
    out = io.StringIO()
    argv = sys.argv[:]
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
            try:
                status = entry.main([name, *map(str, args)])
            except SystemExit as e:
                status = e.code if isinstance(e.code, int) else 1
    finally:
        sys.argv = argv  # the entry point names the report in sys.argv
    return status, out.getvalue()


def paper_report(data, docs, script=False):
    """scripts/paper_report.sh on DATA into DOCS (the page DOCS/paper_comparison.md, its figures, the
    tables published into DATA/report/): with `script` the script itself, else its steps in this
    process: `vppdem.report paper assemble`, `vppdem sweep --report-only` of each study with runs,
    its tables copied into DATA/report/<study>/, `vppdem.report paper write`. Returns the page."""
    data, docs = str(data), str(docs)
    if script:
        env = dict(os.environ, VPPDEM=BINARY, DATA=data, DOCS=docs)
        r = subprocess.run(["bash", os.path.join(SOURCE_DIR, "scripts", "paper_report.sh")], env=env,
                           capture_output=True, text=True)
        assert r.returncode == 0, r.stdout + r.stderr
        return read(os.path.join(docs, "paper_comparison.md"))
    from vppdem.report import paper
    with tempfile.TemporaryDirectory() as tmp, contextlib.chdir(SOURCE_DIR):
        listing = io.StringIO()
        with contextlib.redirect_stdout(listing):
            paper.assemble(data, tmp, BINARY)
        for line in listing.getvalue().splitlines():
            name, toml, n = line.split()
            if int(n) <= 0:
                continue
            r = subprocess.run([BINARY, "sweep", toml, "--out", os.path.join(tmp, name), "--report-only", "--quiet"],
                               capture_output=True, text=True)
            assert r.returncode == 0, r.stdout + r.stderr
            os.makedirs(os.path.join(data, "report", name), exist_ok=True)
            for f in ("summary.csv", "summary_cases.csv", "summary_paired.csv", "sources.csv"):
                if os.path.isfile(os.path.join(tmp, name, f)):
                    shutil.copyfile(os.path.join(tmp, name, f), os.path.join(data, "report", name, f))
            if os.path.isfile(os.path.join(data, name, "COMMAND")):
                shutil.copyfile(os.path.join(data, name, "COMMAND"), os.path.join(data, "report", name, "COMMAND"))
        paper.write(os.path.join(data, "report"), os.path.join(docs, "paper_comparison.md"), docs,
                    "bash scripts/paper_report.sh")
    return read(os.path.join(docs, "paper_comparison.md"))


def row(page, claim):
    """A claim's row of the page ("| C9 | ..." to the end of its line); empty when not there."""
    at = page.find(f"| {claim} |")
    return "" if at < 0 else page[at:page.find("\n", at)]


def section(page, head, end="\n## "):
    """A page's section from its heading `head` to the next heading (or to `end`); empty when not
    there."""
    at = page.find(head)
    if at < 0:
        return ""
    stop = page.find(end, at + 3)
    return page[at:] if stop < 0 else page[at:stop]
