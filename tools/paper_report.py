#!/usr/bin/env python3
"""tools/paper_report.py ARGS...: the paper's report, where issue 44 names it; the code is the
package's report `python3 -m vppdem.report paper ARGS...` (src/python/vppdem/report/paper.py,
driven by scripts/paper_report.sh), run here with the same arguments:
    paper_report.py assemble DATA TMP
    paper_report.py write DATA OUT.md FIGDIR --command TEXT
Runs under Debian's /usr/bin/python3 (matplotlib, numpy)."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "src", "python"))
from vppdem.report.__main__ import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(["paper"] + sys.argv[1:]))
