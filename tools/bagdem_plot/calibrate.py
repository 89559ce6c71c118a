"""calibrate.png: calibrate.csv and calibration.json (bagdem calibrate): the ensemble's peak reduction
against the calibrated key, with the targets and the values found."""
import json
import math
import os

import numpy as np

from .figure import MODE_MARKERS, axes_legend, colours, new_figure, save
from .tables import BadInput, read_table


def plot_calibrate(directory, out_dir, written):
    """Per target (mode), the mean reduction of every value run with its 95% interval over the
    seeds, the target as a dashed line, and each solution as a vertical line (a matched one with
    its interval shaded); a log axis when the values span a factor of 3 or more."""
    t = read_table(directory, "calibrate.csv")
    if t is None:
        return
    t.require("mode", "target_db", "reduction_db_mean", "reduction_db_ci95", "round")
    keys = [(n, u, h) for n, u, h in t.columns if "." in n and u is not None]
    if not keys:
        raise BadInput(f"{t.path}: no column `<key> [unit]` with the calibrated values")
    key, unit, header = keys[0]
    x = t.num(header)
    # The values in the unit of the bounds (calibration.json), as the command prints them.
    sol = []
    path = os.path.join(directory, "calibration.json")
    if os.path.isfile(path):
        try:
            with open(path) as f:
                doc = json.load(f)
        except (OSError, ValueError) as e:
            raise BadInput(f"{path}: not readable JSON: {e}") from None
        sol = doc.get("solutions", [])
        if doc.get("to_si"):
            x = x / float(doc["to_si"])
            unit = doc.get("unit") or unit
    modes = t.num("mode")
    fig, axes = new_figure()
    ax = axes[0]
    distinct = sorted({int(m) for m in modes if np.isfinite(m)})
    cs = colours(len(distinct))
    for k, m in enumerate(distinct):
        rows = np.array([i for i in range(t.rows) if modes[i] == m and np.isfinite(t.num("reduction_db_mean")[i])], dtype=int)
        if rows.size == 0:
            continue
        order = rows[np.argsort(x[rows])]
        ci = np.nan_to_num(t.num("reduction_db_ci95", order), nan=0.0)
        ax.errorbar(x[order], t.num("reduction_db_mean", order), yerr=ci, fmt=MODE_MARKERS[k % len(MODE_MARKERS)] + "-",
                    color=cs[k], ms=5, capsize=3, lw=1, label=f"mode {m}: mean over the seeds (95% interval)")
        ax.axhline(t.num("target_db", order)[0], color=cs[k], ls="--", lw=1, label=f"mode {m}: target")
    if np.nanmin(x) > 0 and np.nanmax(x) >= 3 * np.nanmin(x):
        ax.set_xscale("log")
        from matplotlib import ticker
        ax.xaxis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        ax.xaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_formatter(ticker.NullFormatter())
    for s in sol:
        v, hw = s.get("value"), s.get("half_width")
        if v is None:
            continue
        ax.axvline(v, color="0.2", lw=1.2, label="value found" if s.get("matched") else "closest value (not matched)")
        if s.get("matched") and hw is not None and math.isfinite(hw):  # a value not matched has no interval to show
            ax.axvspan(v - hw, v + hw, color="0.5", alpha=0.15, lw=0)
    ax.set_xlabel(f"{key} [{unit}]")
    ax.set_ylabel("peak reduction [dB]")
    ax.set_title("Calibration: the ensemble's peak reduction against the key (shaded: the value's 95% interval)", fontsize=10)
    axes_legend(ax)
    save(fig, out_dir, "calibrate.png", written)
