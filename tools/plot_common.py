"""What the plot tools in tools/ share: one error style, reading a CSV, saving a figure.

The tools run as scripts (/usr/bin/python3 tools/plot_x.py), so Python finds this module
beside them. An error prints one line, "<tool>: error: <message>", and exits with code 2.
"""
import csv
import os
import sys


def fail(msg):
    tool = os.path.splitext(os.path.basename(sys.argv[0]))[0]
    print(f"{tool}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def read_csv_rows(path, columns=(), expected=None):
    """The rows of a CSV with a header line, as dicts; fails unless it has data rows and
    every name in `columns`. `expected` says what the file should be, for a non-text file."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail(f"{path}: cannot open: {e.strerror}")
    except (UnicodeDecodeError, csv.Error):
        fail(f"{path}: not a text CSV" + (f" (expected {expected})" if expected else ""))
    if not rows:
        fail(f"{path}: no data rows")
    for c in columns:
        if c not in rows[0]:
            fail(f"{path}: missing column '{c}'")
    return rows


def save_figure(fig, path, dpi=90):
    try:
        fig.savefig(path, dpi=dpi)
    except OSError as e:
        fail(f"{path}: cannot write: {e.strerror}")
