"""The sweeps' tables: one number format, means over seeds, CSV."""
import csv
import math


def isnum(v):
    """A number from summary.json (an int there too: 1 for 1.0), not None/bool; NaN included."""
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def fmt(v, digits=2, scale=1.0, missing="-", spec=None):
    """A table cell: a float scaled and with `digits` decimals; an int as it
    is (scale 1); `missing` for None and NaN; anything else as str(). spec: a
    format spec (e.g. ".4g") for every number instead of `digits`."""
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return missing
    if isinstance(v, bool) or not isnum(v):
        return str(v)
    if spec:
        return f"{v * scale:{spec}}"
    if isinstance(v, int) and scale == 1.0:
        return str(v)
    return f"{v * scale:.{digits}f}"


def mean(vals):
    """Mean of the finite numbers among vals (NaN when there is none)."""
    vals = [v for v in vals if isnum(v) and v == v]
    return sum(vals) / len(vals) if vals else float("nan")


def write_csv(path, rows, fields=None):
    """rows (dicts) with a header of `fields` (default: the first row's keys;
    keys not in fields are left out)."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields or list(rows[0]), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
