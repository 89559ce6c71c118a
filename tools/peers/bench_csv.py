#!/usr/bin/python3
"""bagdem bench --format csv read by column name (the reader of tools/peers/bench and growth).

  bench_csv.py COLUMN [NAME=VALUE ...] < CSV   prints COLUMN of the one row where each column NAME
                                               holds VALUE (numbers compared as numbers)

Columns are named without their units: `ns_per_particle_step [ns]` is ns_per_particle_step. No row,
or more than one, is an error (exit code 2) that names the columns and what the table holds.
"""
import csv
import sys


class BadInput(Exception):
    """Bad input: exit code 2."""


def read(lines):
    """The CSV's rows as dicts from column name (the header's `name [unit]` without the unit) to cell."""
    rows = [r for r in csv.reader(lines) if r]
    if not rows:
        raise BadInput("empty input; expected the CSV of bagdem bench --format csv")
    names = [h.split(" [")[0].strip() for h in rows[0]]
    for n, r in enumerate(rows[1:], start=2):
        if len(r) != len(names):
            raise BadInput(f"line {n} has {len(r)} cells; the header has {len(names)} columns")
    return [dict(zip(names, r)) for r in rows[1:]]


def same(cell, value):
    try:
        return float(cell) == float(value)
    except ValueError:
        return cell == value


def pick(rows, column, where):
    """The number in `column` of the one row where every (name, value) of `where` holds."""
    names = rows[0].keys() if rows else []
    for name in [column] + [n for n, _ in where]:
        if rows and name not in names:
            raise BadInput(f"no column '{name}'; columns: {', '.join(names)}")
    hits = [r for r in rows if all(same(r[n], v) for n, v in where)]
    if len(hits) != 1:
        said = ", ".join(f"{n} = {v}" for n, v in where) or "any row"
        raise BadInput(f"{len(hits)} rows with {said} (expected one) among {len(rows)}")
    return float(hits[0][column])


def main(argv):
    if not argv or any("=" not in a for a in argv[1:]):
        raise BadInput(__doc__.strip())
    where = [tuple(a.split("=", 1)) for a in argv[1:]]
    print(f"{pick(read(sys.stdin), argv[0], where):.12g}")


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except BadInput as e:
        sys.stderr.write(f"bench_csv.py: {e}\n")
        sys.exit(2)
