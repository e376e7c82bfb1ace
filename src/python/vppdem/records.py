"""The records of vppdem's runs as Python reads them: CSV tables (forces.csv, cycles.csv,
summary.csv, ...) and the one way a tool stops on a bad one.

Needs numpy only (not the compiled module), so the plots (vppdem.plot), the reports (vppdem.report)
and the scripts of tools/ share it: ``sys.path.insert(0, "<repo>/src/python")`` then
``from vppdem.records import ...``.
"""

import csv
import gzip
import math
import os
import sys

import numpy as np


class RecordError(ValueError):
    """A record that is missing, unreadable, empty or lacks a column asked of it; the message
    names the file and what is wrong."""


def fail(msg, status=1):
    """Ends a script: `NAME: msg` on stderr (NAME: the script's file name, as argparse names it)
    and exit status `status`."""
    print(f"{os.path.basename(sys.argv[0])}: {msg}", file=sys.stderr)
    sys.exit(status)


def finite_number(x):
    """A cell's text (or any value) as a finite float; None when it is empty, not a number, NaN or
    infinite."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def _rows(path):
    """The rows of a CSV file as lists of text, blank lines and `#` comment lines left out; a path
    ending in .gz is read through gzip (a published record: tools.csv.gz)."""
    try:
        with (gzip.open(path, "rt", newline="") if os.fspath(path).endswith(".gz") else open(path, newline="")) as f:
            return [r for r in csv.reader(f) if r and any(c.strip() for c in r) and not r[0].startswith("#")]
    except FileNotFoundError:
        raise RecordError(f"{path} not found") from None
    except (OSError, EOFError) as e:  # gzip: BadGzipFile is an OSError, a cut file an EOFError
        raise RecordError(f"cannot read {path}: {getattr(e, 'strerror', None) or e}") from None


def read_table(path):
    """(header, rows) of a CSV file with a header: the column names and each data row as
    {name: text}; ([], []) for a file without a line."""
    rows = _rows(path)
    if not rows:
        return [], []
    header = [c.strip() for c in rows[0]]
    return header, [dict(zip(header, r)) for r in rows[1:]]


# The records' columns that count or index (cycles.csv, forces.csv, summary.csv): read as
# integers when every value is a whole number (an empty or fractional cell keeps the column float).
INTEGER_COLUMNS = frozenset({"cycle", "settled", "settled_cycles", "first_settled_cycle", "grains", "simulation.seed",
                             "samples", "n"})


def read_csv(path, columns=None):
    """{column: array} for the named columns (None: every column) of a CSV file with a header and
    at least one data row: floats, and integers for the counting columns (INTEGER_COLUMNS)."""
    rows = _rows(path)
    if not rows:
        raise RecordError(f"{path} is empty")
    header = [c.strip() for c in rows[0]]
    columns = header if columns is None else columns
    missing = [c for c in columns if c not in header]
    if missing:
        raise RecordError(f"{path}: missing column(s) {', '.join(missing)} (columns: {', '.join(header)})")
    if len(rows) < 2:
        raise RecordError(f"{path} has a header but no data rows")
    out = {}
    for name in columns:
        k = header.index(name)
        try:
            out[name] = np.array([float(r[k]) for r in rows[1:]])
        except (ValueError, IndexError) as e:
            raise RecordError(f"{path}: bad value in column {name}: {e}") from None
        if name in INTEGER_COLUMNS and np.all(np.isfinite(out[name])) and np.all(out[name] == np.round(out[name])):
            out[name] = out[name].astype(np.int64)
    return out
