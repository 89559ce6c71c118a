"""Every output of a bagdem command read back: its CSV tables as pandas frames, its JSON as dicts,
results.h5 as numpy arrays, a study's points, and tools/plot's figures."""
import glob
import json
import os
import re
import subprocess
import sys

import numpy as np
import pandas as pd

from .command import ROOT

# The tables bagdem writes (docs/outputs.md), each an attribute of Results: results.peaks reads
# peaks.csv. A study's merged tables have the same names; `<table>_ensemble` its means over seeds.
TABLES = ("sweep", "peaks", "reduced", "compare", "bare_curve", "drop", "drop_result", "map", "predict",
          "predict_peaks", "predict_random", "design", "calibrate", "trade", "export", "modes")

# How bagdem writes a missing number: nothing, or C's "nan" / "-nan" (0/0 printed with %g).
MISSING = ["", "nan", "-nan", "NaN", "-NaN"]


def read_table(path):
    """A bagdem CSV table as a pandas DataFrame. Columns keep their headers exactly as written
    (`reduction_dB [dB]`, docs/outputs.md). A column with a unit holds floats (NaN where bagdem
    wrote none); one without a unit (`status`, a study's `bag.balls.diameter` = `4 mm`) or with the
    unit `text` holds strings, or numbers when every cell is one (`point`, `seed`).
    frame.attrs["units"] maps each header to its unit ("" for none). A cell of a unit's column that
    is not a number raises ValueError naming the file, column and cell, never a column of text."""
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{path}: no such table")
    try:
        frame = pd.read_csv(path, keep_default_na=False, na_values=MISSING, dtype=str)
    except pd.errors.EmptyDataError:
        raise ValueError(f"{path}: empty; a bagdem table starts with a header line of `name [unit]` entries") from None
    units = {}
    for column in frame.columns:
        _, _, rest = column.partition(" [")
        units[column] = rest[:-1] if rest.endswith("]") else ""
        if units[column] in ("", "text"):
            converted = pd.to_numeric(frame[column], errors="coerce")
            if not (converted.isna() & frame[column].notna()).any():
                frame[column] = converted
            continue
        converted = pd.to_numeric(frame[column], errors="coerce").astype(float)
        bad = converted.isna() & frame[column].notna()
        if bad.any():
            row = int(bad.idxmax())
            raise ValueError(f"{path}: column '{column}' row {row + 1}: {frame[column][row]!r} is not a number")
        frame[column] = converted
    frame.attrs["units"] = units
    frame.attrs["path"] = os.path.abspath(path)
    return frame


class H5:
    """results.h5 (or a study's study.h5) read by dataset path, each a numpy array read when asked:
    h5["cavity/time"]; `names` lists them (docs/outputs.md describes each)."""

    def __init__(self, path):
        import h5py  # imported here: reading tables does not need it
        self.path = path
        self._h5py = h5py
        if not os.path.isfile(path):
            raise FileNotFoundError(f"{path}: no such file")
        with h5py.File(path, "r") as f:
            self.names = []
            f.visititems(lambda name, obj: self.names.append(name) if isinstance(obj, h5py.Dataset) else None)

    def __getitem__(self, name):
        name = name.lstrip("/")
        if name not in self.names:
            raise KeyError(f"{self.path} has no dataset {name!r}; it has: {', '.join(self.names)}")
        with self._h5py.File(self.path, "r") as f:
            return np.asarray(f[name][()])

    def __contains__(self, name):
        return name.lstrip("/") in self.names


class Results:
    """An output directory of a bagdem command (a run's, a study's, a map's, a prediction's, a
    design's or a calibration's). Tables are attributes (results.peaks, results.reduced, ...: see
    TABLES), read when asked; so are summary (summary.json), calibration (calibration.json),
    map_info (map.json), h5 (results.h5, else study.h5) and points (a study's point-NNN)."""

    def __init__(self, path):
        self.path = os.path.abspath(path)
        if not os.path.isdir(self.path):
            raise FileNotFoundError(f"{self.path}: no such output directory")

    def __repr__(self):
        return f"Results({self.path!r})"

    def file(self, name):
        return os.path.join(self.path, name)

    def tables(self):
        """The tables this directory holds, by name (peaks, peaks_ensemble, ...)."""
        return sorted(os.path.splitext(os.path.basename(p))[0] for p in glob.glob(self.file("*.csv")))

    def table(self, name):
        """NAME.csv as a DataFrame (read_table); a missing table raises FileNotFoundError naming those
        present."""
        path = self.file(name + ".csv")
        if not os.path.isfile(path):
            raise FileNotFoundError(f"{self.path} has no {name}.csv; it has: {', '.join(self.tables()) or 'no table'}")
        return read_table(path)

    def __getattr__(self, name):
        # A table as an attribute; a missing one is an AttributeError (so hasattr and getattr with
        # a default work), with the message of table().
        base = name[:-len("_ensemble")] if name.endswith("_ensemble") else name
        if base not in TABLES:
            raise AttributeError(name)
        try:
            return self.table(name)
        except FileNotFoundError as e:
            raise AttributeError(str(e)) from None

    def json(self, name):
        with open(self.file(name)) as f:
            return json.load(f)

    @property
    def summary(self):
        return self.json("summary.json")

    @property
    def design_pairs(self):
        """design-pairs.csv (bagdem design --dampers 2: pairs of bags ranked; docs/bag-design.md)."""
        return self.table("design-pairs")

    @property
    def calibration(self):
        return self.json("calibration.json")

    @property
    def map_info(self):
        return self.json("map.json")

    @property
    def h5(self):
        return H5(self.file("results.h5") if os.path.isfile(self.file("results.h5")) else self.file("study.h5"))

    @property
    def points(self):
        """A study's points (point-NNN, in order), each a Results."""
        points = [p for p in glob.glob(self.file("point-*")) if re.fullmatch(r"point-[0-9]{3,}", os.path.basename(p))]
        return [Results(p) for p in sorted(points, key=lambda p: int(os.path.basename(p)[len("point-"):]))]

    @property
    def dampers(self):
        """A case of several dampers ([[dampers]]): each damper's but the case's own (this directory's)
        results, by name (OUT/dampers/NAME), each a Results; {} for a case of one."""
        root = self.file("dampers")
        names = sorted(n for n in os.listdir(root) if os.path.isdir(os.path.join(root, n))) if os.path.isdir(root) else []
        return {n: Results(os.path.join(root, n)) for n in names}

    def plot(self, out=None):
        """tools/plot's figures of this directory (into OUT, default the directory): their paths."""
        args = [sys.executable, os.path.join(ROOT, "tools", "plot"), self.path] + (["--out", os.path.abspath(out)] if out else [])
        done = subprocess.run(args, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"tools/plot {self.path} exited {done.returncode}:\n{done.stderr}")
        return [line for line in done.stdout.splitlines() if line.endswith(".png")]
