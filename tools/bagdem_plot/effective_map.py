"""map.png: map.csv (bagdem characterize): the damper's effective field, each figure against the
acceleration ratio Gamma (log axis), a line per frequency, with its 95% interval over the starts."""
import numpy as np

from .figure import MODE_MARKERS, colours, new_figure, readable_log_axis, save
from .tables import read_table

PANELS = (("M_eff_ratio", "M_eff / M_bag"), ("Cb_over_Mbw", "C_b / (M_b w)"), ("loss_factor", "loss factor"), ("e", "restitution e"))


def plot_map(directory, out_dir, written):
    t = read_table(directory, "map.csv")
    if t is None:
        return
    t.require("gamma", "frequency", *[name for name, _ in PANELS], *[name + "_ci95" for name, _ in PANELS])
    gamma, freq = t.num("gamma"), t.num("frequency")
    fig, axes = new_figure(len(PANELS), height=9.0)
    freqs = sorted(set(freq[np.isfinite(freq)]))
    cs = colours(len(freqs))
    for k, f in enumerate(freqs):
        rows = np.array([i for i in range(t.rows) if freq[i] == f], dtype=int)
        rows = rows[np.argsort(gamma[rows])]
        for ax, (name, _) in zip(axes, PANELS):
            y = t.num(name, rows)
            ci = np.nan_to_num(t.num(name + "_ci95", rows), nan=0.0)
            ax.errorbar(gamma[rows], y, yerr=ci, fmt=MODE_MARKERS[k % len(MODE_MARKERS)] + "-", ms=4, capsize=2, color=cs[k],
                        label=f"{f:.4g} Hz")
    for ax, (_, label) in zip(axes, PANELS):
        ax.set_ylabel(label)
        ax.set_xscale("log")
        readable_log_axis(ax)
    axes[-1].set_xlabel("Gamma = X w^2 / g")
    axes[0].set_title("Effective field of the damper under prescribed motion (bars: 95% over the starts)", fontsize=10)
    save(fig, out_dir, "map.png", written, below=axes[0])
