"""docs/robustness.md's section on the settings table, and its figure, from the property test's CSV.

usage: python3 -m vppdem.report robustness CSV DOCS COMMAND COMMIT
  CSV      the outcomes written by scripts/robustness.sh (VPPDEM_PROPERTY_CSV of the test
           SettingsProperty.EveryValueIsRefusedOrRunsEveryCycleFinite): one row per (key, value)
  DOCS     the folder of robustness.md; the figure goes to DOCS/robustness_settings.png
  COMMAND  the command that made the CSV (written under the figure)
  COMMIT   the commit the runs were made on

Replaces the text between the markers <!-- settings-property:begin --> and
<!-- settings-property:end --> in robustness.md (appends them the first time): the outcomes per
key as a figure (refused / ran / failed, a known finding of issue 48 apart), and every failing
(key, value, outcome). Runs under /usr/bin/python3 (matplotlib).
"""
import csv
import os
import sys
from collections import OrderedDict

BEGIN = "<!-- settings-property:begin -->"
END = "<!-- settings-property:end -->"
OUTCOMES = ["refused", "ran", "failed (issue 48)", "failed", "skipped"]
COLOURS = {"refused": "#4c72b0", "ran": "#55a868", "failed (issue 48)": "#dd8452", "failed": "#c44e52",
           "skipped": "#cccccc"}


# The findings of issue 48 that a failure belongs to, by its key and outcome (the test's
# kKnownFailing holds only the cases that CI draws): (label, predicate on the CSV row).
FINDINGS = [
    ("a refusal with \"cannot create std::vector larger than max_size()\" (dt_safety=0.7, "
     "foil.stiffness_ratio=1.5, simulation.local_damping=0)",
     lambda r: "max_size()" in r["detail"]),
    ("process.cycles / samples_per_cycle wrap in int (2147483648: 0 cycles; 4294967297: 1)",
     lambda r: r["key"] in ("process.cycles", "process.samples_per_cycle") and "cycles of" in r["detail"]),
    ("a run that completes fewer cycles than asked exits 0 (too high a frequency, a huge velocity)",
     lambda r: r["outcome"] == "failed" and "cycles of" in r["detail"]),
    ("a refusal that blames another key (damper.radius=1e300 blames grains.radius)",
     lambda r: "without naming the key" in r["detail"] and "config key '" in r["detail"]),
    ("a run still going at its time limit: one that never ends (pump_speed=1e-12: 215,128 h left), or only "
     "slow on a loaded machine (a time step 100 times smaller)",
     lambda r: "still running" in r["detail"]),
]


def finding_of(row):
    for label, match in FINDINGS:
        if match(row):
            return label
    return ""


def outcome_of(row):
    if row["outcome"] == "failed" and (row["known"] == "yes" or finding_of(row)):
        return "failed (issue 48)"
    return row["outcome"]


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 4:
        sys.exit(__doc__)
    path, docs, command, commit = argv
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("vppdem.report robustness: %s holds no cases" % path)
    per_key = OrderedDict()
    for r in rows:
        per_key.setdefault(r["key"], {o: 0 for o in OUTCOMES})[outcome_of(r)] += 1

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keys = list(per_key)
    fig, ax = plt.subplots(figsize=(8, 0.22 * len(keys) + 1.2))
    left = [0] * len(keys)
    for o in OUTCOMES:
        n = [per_key[k][o] for k in keys]
        if not any(n):
            continue
        ax.barh(range(len(keys)), n, left=left, color=COLOURS[o], label=o, height=0.8)
        left = [a + b for a, b in zip(left, n)]
    ax.set_yticks(range(len(keys)))
    ax.set_yticklabels(keys, fontsize=7)
    ax.set_ylim(len(keys) - 0.5, -0.5)
    ax.set_xlabel("values drawn (within the range, at its edges, just outside, the type's extremes)")
    ax.legend(fontsize=7, loc="lower right")
    ax.set_title("Settings table property test: outcome per key (seed %s)" % rows[0]["seed"], fontsize=9)
    fig.tight_layout()
    png = os.path.join(docs, "robustness_settings.png")
    fig.savefig(png, dpi=110)

    total = {o: sum(per_key[k][o] for k in keys) for o in OUTCOMES}
    cpu = sum(float(r["cpu_s"] or 0) for r in rows)
    lines = [BEGIN, "",
             "Made by `%s` on %s (%d cases, %.0f s of CPU in the runs; the CSV: `%s`)." %
             (command, commit, len(rows), cpu, os.path.relpath(path, os.path.dirname(docs.rstrip("/")) or ".")),
             "",
             "| refused | ran | failed (a finding of issue 48) | failed (other) | skipped |",
             "|---|---|---|---|---|",
             "| %d | %d | %d | %d | %d |" % tuple(total[o] for o in OUTCOMES),
             "",
             "![outcomes per key](robustness_settings.png)",
             ""]
    failed = [r for r in rows if r["outcome"] == "failed"]
    if failed:
        labels = []
        for r in failed:
            f = finding_of(r)
            if f and f not in labels:
                labels.append(f)
        lines += ["Every failing case; the finding of issue 48 it belongs to (by its key and outcome):", ""]
        lines += ["%d. %s" % (i + 1, f) for i, f in enumerate(labels)]
        lines += ["", "| key | value | kind | run | issue 48 | outcome |", "|---|---|---|---|---|---|"]
        def finding_number(r):
            f = finding_of(r)
            n = str(labels.index(f) + 1) if f else "new"
            return n + (" (CI: known)" if r["known"] == "yes" else "")

        for r in failed:
            detail = r["detail"].replace("|", "\\|")
            if len(detail) > 200:
                detail = detail[:200] + "..."
            lines.append("| `%s` | `%s` | %s | %s | %s | %s |" %
                         (r["key"], r["value"] if len(r["value"]) < 40 else r["value"][:37] + "...", r["kind"],
                          r["route"], finding_number(r), detail))
        lines.append("")
    lines.append(END)
    section = "\n".join(lines) + "\n"

    md_path = os.path.join(docs, "robustness.md")
    with open(md_path) as f:
        md = f.read()
    if BEGIN in md and END in md:
        a = md.index(BEGIN)
        b = md.index(END) + len(END)
        md = md[:a] + section.rstrip("\n") + md[b:]
    else:
        md = md.rstrip("\n") + "\n\n" + section
    with open(md_path, "w") as f:
        f.write(md)
    print("wrote %s and %s" % (md_path, png))


if __name__ == "__main__":
    main(sys.argv[1:])
