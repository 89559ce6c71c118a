"""bagdem's output tables (CSV) read by column name: `name [unit]` headers, text columns, a study's
varied keys, failed points and seeds, and an ensemble's means and error bars (tools/plot's header
states the conventions)."""
import csv
import math
import os
import re
import sys

import numpy as np

HEADER_ENTRY = re.compile(r"^(.*?)\s*\[(.*)\]$")


class BadInput(Exception):
    """Bad input: exit code 2."""


def note(message):
    sys.stderr.write(f"tools/plot: {message}\n")


# ---------------------------------------------------------------------------------------------
# Tables


class Table:
    """A CSV table read by column name. A column with a unit holds numbers (NaN for an empty cell),
    except the unit `text` (e.g. reduced.csv's `e_method [text]`); one without a unit, or with
    `text`, keeps its strings, and a numeric view when every cell is a number."""

    def __init__(self, path):
        self.path = path
        try:
            with open(path, newline="") as f:
                lines = [(n, r) for n, r in enumerate(csv.reader(f), start=1) if any(c.strip() for c in r)]
        except OSError as e:
            raise OSError(f"{path}: cannot read: {e.strerror}") from e
        if not lines:
            raise BadInput(f"{path}: empty; a table starts with a header line of `name [unit]` entries")
        header = [h.strip() for h in lines[0][1]]
        body = lines[1:]
        for n, r in body:
            if len(r) != len(header):
                raise BadInput(f"{path}: line {n} has {len(r)} cells; the header has {len(header)} columns")
        self.rows = len(body)
        self.columns = []  # (name, unit or None, header text) in file order
        self.numbers, self.strings = {}, {}  # header text -> float array / list of str
        for k, h in enumerate(header):
            m = HEADER_ENTRY.match(h)
            name, unit = (m.group(1), m.group(2)) if m else (h, None)
            if unit == "text":
                unit = None
            self.columns.append((name, unit, h))
            cells = [r[k].strip() for _, r in body]
            if unit is None:
                self.strings[h] = cells
            try:
                self.numbers[h] = np.array([float(c) if c else math.nan for c in cells], dtype=float)
            except ValueError:
                if unit is not None:
                    n, c = next((n, r[k].strip()) for n, r in body if not is_number(r[k]))
                    raise BadInput(f"{path}: line {n}, column '{h}' = '{c}': a column with a unit holds "
                                   "numbers (or an empty cell)") from None

    def names(self):
        return [n for n, _, _ in self.columns]

    def _header(self, name, numeric):
        """The header of column `name` (a bare name, or `name [unit]` exactly), or None. A numeric
        lookup prefers the column with a unit, a text lookup the one without."""
        pool = self.numbers if numeric else {**self.numbers, **self.strings}
        if name in pool:
            return name
        hits = [(u, h) for n, u, h in self.columns if n == name and h in pool]
        preferred = [h for u, h in hits if (u is not None) == numeric]
        return (preferred or [h for _, h in hits] or [None])[0]

    def has(self, name):
        """Whether a numeric column `name` exists."""
        return self._header(name, True) is not None

    def has_any(self, name):
        return self._header(name, False) is not None

    def num(self, name, rows=None):
        h = self._header(name, True)
        if h is None:
            raise BadInput(f"{self.path}: no numeric column '{name}'; columns found: {', '.join(self.names())}")
        return self.numbers[h] if rows is None else self.numbers[h][rows]

    def opt(self, name, rows=None):
        return self.num(name, rows) if self.has(name) else None

    def text(self, name, rows=None):
        """The cells of column `name` as strings (a numeric column's values formatted)."""
        h = self._header(name, False)
        v = self.strings[h] if h in self.strings else [f"{x:g}" for x in self.numbers[h]]
        return v if rows is None else [v[i] for i in rows]

    def label(self, name):
        h = self._header(name, True)
        return h if h is not None and HEADER_ENTRY.match(h) else name

    def require(self, *names):
        missing = [n for n in names if not self.has(n)]
        if missing:
            raise BadInput(f"{self.path}: column {', '.join(repr(n) for n in missing)} missing; required: "
                           f"{', '.join(names)}; columns found: {', '.join(self.names())}")

    # --- a study's tables

    def varied_keys(self):
        """The varied case keys (the dotted column names), in file order."""
        return list(dict.fromkeys(n for n in self.names() if "." in n))

    def is_study(self):
        return self.has_any("point") or bool(self.varied_keys())

    def good_rows(self):
        """The rows to draw: a study's failed points are left out."""
        if not self.has_any("status"):
            return np.arange(self.rows)
        return np.array([i for i, s in enumerate(self.text("status")) if not s.lower().startswith("fail")], dtype=int)

    def seeds_vary(self):
        return self.has_any("seed") and len(set(self.text("seed"))) > 1

    def point_keys(self, rows):
        """What names each row's study point: the `point` column, else the varied keys (and seed)."""
        cols = ["point"] if self.has_any("point") else self.varied_keys() + (["seed"] if self.has_any("seed") else [])
        texts = [self.text(c, rows) for c in cols]
        return [tuple(t[j] for t in texts) for j in range(len(rows))]

    def point_label(self, row):
        """"diameter = 4 mm, material = ldpe" (the varied keys' last parts), and the seed if seeds vary."""
        parts = [f"{k.split('.')[-1]} = {self.text(k, [row])[0]}" for k in self.varied_keys()]
        if not parts and self.has_any("point"):
            parts = [f"point {self.text('point', [row])[0]}"]
        if self.seeds_vary():
            parts.append(f"seed {self.text('seed', [row])[0]}")
        return ", ".join(parts)


def is_number(cell):
    try:
        float(cell)
        return True
    except ValueError:
        return not cell.strip()


def read_table(directory, name):
    path = os.path.join(directory, name)
    return Table(path) if os.path.isfile(path) else None


def groups_by_point(t):
    """[(label, rows)]: one group per study point in order of first appearance, or one unlabelled
    group for a single run."""
    rows = t.good_rows()
    if not t.is_study():
        return [("", rows)]
    members = {}
    for i, k in zip(rows, t.point_keys(rows)):
        members.setdefault(k, []).append(i)
    return [(t.point_label(v[0]), np.array(v, dtype=int)) for v in members.values()]


def mean_col(t, name, rows=None):
    """An ensemble's mean of `name` (`name_mean`, else `name`)."""
    return t.num(name + "_mean", rows) if t.has(name + "_mean") else t.num(name, rows)


def has_mean(t, name):
    return t.has(name + "_mean") or t.has(name)


def err_col(t, name, rows=None):
    """The error bar of `name`: its standard error, else its standard deviation; None if neither."""
    for suffix in ("_se", "_sd"):
        if t.has(name + suffix):
            return t.num(name + suffix, rows)
    return None


def sorted_by_frequency(t, rows):
    """The rows in order of frequency (a sweep's refinement points come after its planned ones)."""
    return rows[np.argsort(t.num("frequency", rows), kind="stable")]


def finite(*arrays):
    mask = np.ones(len(arrays[0]), dtype=bool)
    for a in arrays:
        if a is not None:
            mask &= np.isfinite(a)
    return mask
