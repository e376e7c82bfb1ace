"""The reports of vppdem's studies: the pages of docs/ and their figures, made from the published
records (docs/data/) or from run folders. From the shell:

    python3 -m vppdem.report NAME ARGS...      (PYTHONPATH=src/python; Debian's /usr/bin/python3)
    python3 -m vppdem.report NAME --help       (NAME's usage)

    paper            docs/paper_comparison.md and docs/paper_*.png: `paper assemble DATA TMP`, then
                     `paper write DATA OUT.md FIGDIR --command TEXT` (scripts/paper_report.sh)
    operation        docs/operation.md and its figures (examples/operation/run.sh)
    grain_shapes     docs/grains.md and docs/grains_shapes.png (after scripts/grain_shapes.sh)
    robustness       docs/robustness.md's settings-table section (scripts/robustness.sh)
    paired_velocity  paired velocity convergence of a sweep with seeds (scripts/trust_studies.sh)
    velocity_cycles  velocity convergence cycle by cycle (scripts/velocity_convergence.sh)
    paper_velocity_cycle1  cycle 1 at the paper's velocity beside the velocity study's
                     (docs/data/paper_velocity_cycle1.csv, scripts/trust_studies.sh)
    friction_split   the dissipation split against grain friction (docs/energy_split_friction.png)
    foil             a foil VTK frame rendered to PNG (docs/envelope_0.01MPa.png)
    device           docs/devices.md's study tables and figures (after scripts/device_study.sh), or
                     any device study's folder: FOLDER/device_report.md and .png
    device_slices    side views of a device run's VTK frames (docs/devices_gripper.png)
    membrane_cylinder  the damper's W with the lattice foil against the mesh foil (docs/data/membrane_cylinder/report.md)

Their statistics are one module, vppdem.report.stats (Student's t by the method of
src/vpp/analysis/stats.cpp, the 95% interval, paired and Welch differences); the paper's decision rules
are vppdem.report.rules, the one set of every page. Needs numpy and matplotlib, not the compiled module.
"""
import os

# NAME -> (module, what it makes): the reports `python3 -m vppdem.report NAME` runs.
REPORTS = {
    "paper": ("paper", "docs/paper_comparison.md and its figures (assemble DATA TMP | write DATA OUT.md FIGDIR --command TEXT)"),
    "operation": ("operation", "docs/operation.md and its figures (DATA DOCS [--runs OUT]: first the runs' last cycles into DATA)"),
    "grain_shapes": ("grain_shapes", "docs/grains.md and its figure (DATA DOCS [--bench FILE] [--pressure DIR] [--study FILE])"),
    "robustness": ("robustness", "docs/robustness.md's settings-table section (CSV DOCS COMMAND COMMIT)"),
    "paired_velocity": ("paired_velocity", "paired velocity convergence of a sweep (DIR [--key K] [--quantities Q] [--out PREFIX])"),
    "velocity_cycles": ("velocity_cycles", "velocity convergence cycle by cycle (SWEEP_DIR [--extra DIR ...] [--reference V] [--out PREFIX])"),
    "paper_velocity_cycle1": ("paper_velocity_cycle1", "cycle 1 at the paper's velocity beside the velocity study's (VELOCITY_DIR PAPER_DIR [--seed S] [--out FILE])"),
    "friction_split": ("friction_split", "the dissipation split against grain friction (OUT.png DIR [DIR ...] [--cycle N])"),
    "foil": ("foil", "a foil VTK frame rendered to PNG (FRAME.vtk OUT.png [--title TEXT])"),
    "device": ("device", "docs/devices.md's tables and figures of a device study, its trends table and rules (gripper | gripper_pour | beam | trends), or any device study's folder's report (FOLDER [--out DIR] [--test Welch|paired])"),
    "device_slices": ("device_slices", "side views of a device run (OUT.png FRAME.vtk ... [--titles T] [--sphere R])"),
    "membrane_cylinder": ("membrane_cylinder", "the lattice foil's W against the mesh foil's (DATA: docs/data/membrane_cylinder)"),
}

__all__ = ["REPORTS", "source_dir"]


def source_dir():
    """The repository the reports read their defaults from (studies/...): VPPDEM_SOURCE_DIR when
    set, else the tree this package sits in (src/python/vppdem/report), else the working folder."""
    env = os.environ.get("VPPDEM_SOURCE_DIR")
    if env:
        return env
    d = os.path.dirname(os.path.abspath(__file__))
    for _ in range(4):
        d = os.path.dirname(d)
    return d if os.path.isdir(os.path.join(d, "studies")) else os.getcwd()
