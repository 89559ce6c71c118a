"""predict.png: predict.csv (bagdem predict): per force level and mode, the response at x_a with the
map's damper (every branch of the single-harmonic balance) against the bare structure's."""
import numpy as np

from .figure import axes_legend, colours, new_figure, save
from .tables import read_table


def plot_prediction(directory, out_dir, written):
    t = read_table(directory, "predict.csv")
    if t is None:
        return
    t.require("force", "mode", "frequency", "branch", "response", "bare_response")
    force, mode, freq, branch = t.num("force"), t.num("mode"), t.num("frequency"), t.num("branch")
    panels = sorted({int(m) for m in mode if np.isfinite(m)})
    fig, axes = new_figure(len(panels), height=3.6 * len(panels))
    levels = sorted({f for f in force if np.isfinite(f)})
    cs = colours(len(levels))
    for ax, m in zip(axes, panels):
        for k, F in enumerate(levels):
            rows = np.array([i for i in range(t.rows) if mode[i] == m and force[i] == F], dtype=int)
            if rows.size == 0:
                continue
            order = rows[np.argsort(freq[rows])]
            first = order[branch[order] == 0]
            ax.plot(freq[first], t.num("bare_response", first), "--", color=cs[k], lw=1, label=f"{F:.3g} N, bare")
            for b in sorted({int(x) for x in branch[order]}):
                sel = order[branch[order] == b]
                ax.plot(freq[sel], t.num("response", sel), ".", ms=2.5, color=cs[k], label=f"{F:.3g} N, with the damper" if b == 0 else None)
        ax.set_yscale("log")
        ax.set_ylabel(f"mode {m}: |Y| at x_a [m]")
        axes_legend(ax)
    axes[-1].set_xlabel("frequency [Hz]")
    axes[0].set_title("Prediction from the effective-field map (every branch of the harmonic balance)", fontsize=10)
    save(fig, out_dir, "predict.png", written)
