"""What every figure shares: matplotlib on the Agg backend, the size and resolution, the grid, the
legend below the panels, the colours and markers, the log axis's labels and the dB-percent axis."""
import math
import os

import matplotlib
import numpy as np

_pyplot = None


def plt():
    """matplotlib.pyplot on the Agg backend, imported on first use (most of the start-up time), so
    bad input is refused before paying for it."""
    global _pyplot
    if _pyplot is None:
        matplotlib.use("Agg")
        from matplotlib import pyplot
        _pyplot = pyplot
    return _pyplot


DPI = 150
WIDTH = 7.5  # inches: 1125 pixels at 150 dpi

MODE_MARKERS = ("o", "s", "^", "D", "v", "P")
MODE_LINES = ("-", "--", "-.", ":")


def new_figure(panels=1, height=4.8, ratios=None):
    fig, axes = plt().subplots(panels, 1, figsize=(WIDTH, height), sharex=True, squeeze=False,
                               gridspec_kw={"height_ratios": ratios} if ratios else None)
    axes = list(axes[:, 0])
    for ax in axes:
        ax.grid(True, which="major", alpha=0.45)
        ax.grid(True, which="minor", alpha=0.15)
    return fig, axes


def axes_legend(ax, **kw):
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=9, framealpha=0.85, **kw)


def save(fig, out_dir, name, written, below=None):
    """Lays the figure out and queues it for writing. `below`: axes (one or a list) whose legend
    entries go under the panels, where many entries hide no data; the figure grows to hold them."""
    rect = (0, 0, 1, 1)
    entries = {}
    for ax in ([] if below is None else below if isinstance(below, list) else [below]):
        for handle, label in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(label, handle)
    if entries:
        ncol = 1 if max(len(s) for s in entries) > 48 else 2
        extra = 0.18 * math.ceil(len(entries) / ncol) + 0.1
        w, h = fig.get_size_inches()
        fig.set_size_inches(w, h + extra)
        rect = (0, extra / (h + extra), 1, 1)
        fig.legend(list(entries.values()), list(entries), loc="lower center", ncol=ncol, fontsize=8.5,
                   frameon=False, bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=rect)
    written.append((fig, os.path.join(out_dir, name)))  # written by main once every figure is drawn


def colours(n):
    cycle = plt().rcParams["axes.prop_cycle"].by_key()["color"]
    if n <= len(cycle):
        return cycle[:n]
    return [plt().get_cmap("viridis")(k / (n - 1)) for k in range(n)]


def readable_log_axis(ax):
    """Labels 1-2-5 ticks on a log axis spanning under three decades (matplotlib would label only
    the powers of ten there, often one or none)."""
    lo, hi = ax.get_ylim()
    if lo > 0 and hi / lo < 1e3:
        def fmt(v, _):
            if 1e-2 <= v < 1e4:
                return f"{v:g}"
            e = math.floor(math.log10(v))
            m = v / 10 ** e
            return rf"${m:g}\times10^{{{e}}}$" if abs(m - 1) > 1e-9 else rf"$10^{{{e}}}$"
        from matplotlib import ticker
        ax.yaxis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        ax.yaxis.set_major_formatter(ticker.FuncFormatter(fmt))
        ax.yaxis.set_minor_formatter(ticker.NullFormatter())


def db_to_percent(db):
    return 100.0 * (1.0 - np.power(10.0, -np.asarray(db, dtype=float) / 20.0))


def percent_to_db(p):
    return -20.0 * np.log10(1.0 - np.minimum(np.asarray(p, dtype=float), 100.0 - 1e-9) / 100.0)
