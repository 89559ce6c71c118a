"""design.png: design.csv (bagdem design): each candidate at each position, its predicted worst-mode
peak reduction against its added mass (balls and film, % of the structure's mass), the range over the
map's intervals as a bar; the Pareto front joined; the pairs run coupled with their DEM mean and 95%
interval beside."""
import numpy as np

from .figure import axes_legend, new_figure, save
from .tables import read_table


def plot_design(directory, out_dir, written):
    t = read_table(directory, "design.csv")
    if t is None:
        return
    if not t.has_any("status"):
        t.require("status")
    t.require("mass_ratio", "objective_dB", "objective_dB_lo", "objective_dB_hi", "pareto", "dem_objective_dB",
              "dem_objective_dB_ci95")
    status = t.text("status")
    ranked = np.array([i for i in range(t.rows) if status[i] == "ranked"], dtype=int)
    if ranked.size == 0:
        return
    x = 100 * t.num("mass_ratio", ranked)
    y, lo, hi = t.num("objective_dB", ranked), t.num("objective_dB_lo", ranked), t.num("objective_dB_hi", ranked)
    fig, axes = new_figure(1, height=4.8)
    ax = axes[0]
    ax.errorbar(x, y, yerr=[y - lo, hi - y], fmt="o", ms=3, color="0.6", ecolor="0.8", lw=0.8,
                label="predicted, every candidate and position (range over the map's intervals)")
    front = ranked[t.num("pareto", ranked) == 1]
    order = front[np.argsort(100 * t.num("mass_ratio", front))]
    ax.plot(100 * t.num("mass_ratio", order), t.num("objective_dB", order), "-o", ms=5, color="C0", label="Pareto front (predicted)")
    dem = ranked[np.isfinite(t.num("dem_objective_dB", ranked))]
    if dem.size:
        ax.errorbar(100 * t.num("mass_ratio", dem) + 0.05, t.num("dem_objective_dB", dem), yerr=t.num("dem_objective_dB_ci95", dem),
                    fmt="s", ms=5, color="C3", capsize=3, label="coupled DEM (mean, 95% interval)")
    ax.set_xlabel("added mass [% of the structure's]")
    ax.set_ylabel("worst chosen mode's peak reduction [dB]")
    ax.set_title("bagdem design: reduction against added mass", fontsize=10)
    axes_legend(ax)
    save(fig, out_dir, "design.png", written)
