"""trade.png: trade.csv (bagdem trade): each run's errors against its speed-up, and the noise floor."""
import numpy as np

from .figure import colours, new_figure, save
from .tables import read_table

TRADE_METRICS = [("Cb_over_Mbw", r"$C_b/(M_b\,\omega)$"), ("M_eff_ratio", r"$M_{eff}/M_{bag}$"),
                 ("e_impact", "e (per impact)"), ("energy_per_cycle", "energy per cycle")]


def plot_trade(directory, out_dir, written):
    """trade.csv: each run's error against its speed-up over the reference, a marker per quantity;
    the noise floor (the reference with another seed) as dashed lines; the peak reductions' dB
    differences in a second panel when the case is a sweep."""
    t = read_table(directory, "trade.csv")
    if t is None:
        return
    t.require("speedup")
    runs = t.strings.get("rung") or t.text("rung")
    rows = [i for i in range(t.rows) if runs[i] not in ("reference",) and np.isfinite(t.num("speedup")[i])]
    if not rows:
        return
    db_cols = [n for n in t.names() if n.startswith("reduction_dB mode") and not n.endswith("_error")]
    fig, axes = new_figure(panels=2 if db_cols else 1, height=8.0 if db_cols else 4.8)
    x = t.num("speedup")
    noise = [i for i in range(t.rows) if runs[i] == "reference, seed+1"]
    cs = colours(len(TRADE_METRICS) + len(db_cols))
    ax = axes[0]
    for k, (name, label) in enumerate(TRADE_METRICS):
        if not t.has(name + "_error"):
            continue
        err = 100 * t.num(name + "_error")
        keep = [i for i in rows if np.isfinite(err[i])]
        ax.plot(x[keep], err[keep], "o", color=cs[k], ms=6, label=label)
        if noise and np.isfinite(err[noise[0]]):
            ax.axhline(err[noise[0]], color=cs[k], ls="--", lw=0.9)
    for i in rows:
        ax.annotate(runs[i], xy=(x[i], 1), xycoords=("data", "axes fraction"), textcoords="offset points",
                    xytext=(3, -4), ha="left", va="top", fontsize=7, rotation=90, color="0.35")
    ax.set_xscale("log")
    from matplotlib import ticker
    for a in axes:
        a.xaxis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        a.xaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        a.xaxis.set_minor_formatter(ticker.NullFormatter())
    ax.set_ylabel("error against the reference [%]")
    ax.set_title("Speed/accuracy trade (dashed: the noise floor, the reference with another seed)", fontsize=10)
    if db_cols:
        ax2 = axes[1]
        for k, name in enumerate(db_cols):
            d = t.num(name + "_error")
            keep = [i for i in rows if np.isfinite(d[i])]
            ax2.plot(x[keep], d[keep], "s", color=cs[len(TRADE_METRICS) + k], ms=6, label=name.replace("reduction_dB ", "peak reduction, "))
            if noise and np.isfinite(d[noise[0]]):
                for sign in (1, -1):  # the floor is a spread: either sign
                    ax2.axhline(sign * abs(d[noise[0]]), color=cs[len(TRADE_METRICS) + k], ls="--", lw=0.9)
        ax2.axhline(0.0, color="0.3", lw=0.8)
        ax2.set_ylabel("peak reduction minus the reference's [dB]")
    axes[-1].set_xlabel("speed-up over the reference (its wall time / the run's)")
    save(fig, out_dir, "trade.png", written, below=axes)
