#!/usr/bin/env python3
"""docs/robustness.md's section on the settings table, and its figure, from the property test's CSV.

usage: robustness_report.py CSV DOCS COMMAND COMMIT
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


def outcome_of(row):
    if row["outcome"] == "failed" and row["known"] == "yes":
        return "failed (issue 48)"
    return row["outcome"]


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    path, docs, command, commit = sys.argv[1:]
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("robustness_report.py: %s holds no cases" % path)
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
    ax.invert_yaxis()
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
        lines += ["Every failing case:", "",
                  "| key | value | kind | run | issue 48 | outcome |", "|---|---|---|---|---|---|"]
        for r in failed:
            detail = r["detail"].replace("|", "\\|")
            if len(detail) > 200:
                detail = detail[:200] + "..."
            lines.append("| `%s` | `%s` | %s | %s | %s | %s |" %
                         (r["key"], r["value"] if len(r["value"]) < 40 else r["value"][:37] + "...", r["kind"],
                          r["route"], "known" if r["known"] == "yes" else "", detail))
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
    main()
