"""reduced.png: reduced.csv: C_b/(M_b w), M_eff/M_bag and the restitutions against Gamma (or --x)."""
import numpy as np

from .figure import MODE_MARKERS, axes_legend, colours, new_figure, save
from .tables import HEADER_ENTRY, BadInput, err_col, finite, groups_by_point, note, read_table


RESTITUTIONS = (("e_impact", "from each impact, Eq. (9)"), ("e_eq19a", "inverted from Eq. (19a)"),
                ("e_drop", "drop test"))


def x_column(t, requested):
    if requested is None:
        t.require("gamma")
        return "gamma"
    if not t.has(requested):
        numeric = [h for _, _, h in t.columns if h in t.numbers]
        raise BadInput(f"{t.path}: --x '{requested}': no such numeric column; allowed: {', '.join(numeric)}")
    m = HEADER_ENTRY.match(requested)
    return m.group(1) if m else requested


def plot_reduced(directory, out_dir, x_requested, written):
    t = read_table(directory, "reduced.csv")
    if t is None:
        if x_requested is not None:
            raise BadInput(f"--x '{x_requested}' names a column of reduced.csv, and {directory} has none")
        return
    xname = x_column(t, x_requested)
    t.require("Cb_over_Mbw", "M_eff_ratio")
    if t.rows == 0:
        note(f"{t.path} has no rows: reduced.png not drawn")
        return
    kinds = [(n, what) for n, what in RESTITUTIONS if t.has(n)]
    m_ratio_err = t.opt("M_eff_ratio_se")
    if m_ratio_err is None and t.has("M_eff_se") and t.has("bag_mass"):
        m_ratio_err = t.num("M_eff_se") / t.num("bag_mass")  # M_eff_ratio = M_eff / bag_mass
    groups = groups_by_point(t)
    single = len(groups) == 1
    fig, axes = new_figure(panels=3, height=8.4)

    def draw(ax, y, err, rows, colour, marker, label):
        x, yy = t.num(xname, rows), y[rows]
        e = None if err is None else np.nan_to_num(np.abs(err[rows]))
        keep = finite(x, yy)
        ax.errorbar(x[keep], yy[keep], yerr=None if e is None else e[keep], fmt=marker, color=colour, ms=5,
                    elinewidth=1, capsize=2.5, label=label)

    for (label, rows), c in zip(groups, colours(len(groups))):
        draw(axes[0], t.num("Cb_over_Mbw"), err_col(t, "Cb_over_Mbw"), rows, c, "o", label or None)
        draw(axes[1], t.num("M_eff_ratio"), m_ratio_err, rows, c, "o", None)
        for (n, what), marker, own in zip(kinds, MODE_MARKERS, ("C0", "C1", "C2")):
            # e_impact's bars are the scatter of single impacts (sd); the others' a standard error.
            err = t.opt(n + "_sd") if t.has(n + "_sd") else err_col(t, n)
            draw(axes[2], t.num(n), err, rows, own if single else c, marker, f"{n}: {what}" if single else None)
    if not single:  # colours name the points (legend below), markers the kinds of restitution
        for (n, what), marker in zip(kinds, MODE_MARKERS):
            axes[2].plot([], [], marker, color="0.3", label=f"{n}: {what}")
    axes[0].set_ylabel(r"$C_b/(M_b\,\omega)$ [1]")
    axes[0].set_title("Reduced parameters of the bag (error bars: standard error of the projection)", fontsize=10)
    axes[1].set_ylabel(r"$M_\mathrm{eff}/M_\mathrm{bag}$ [1]")
    axes[1].axhline(1.0, color="0.4", lw=0.8, ls=":")
    axes[2].set_ylabel("restitution e [1]")
    if t.has("e_impact_sd"):
        axes[2].set_title("restitution (e_impact's error bars: standard deviation over the impacts)", fontsize=9)
    axes[2].set_xlabel(r"$\Gamma = X\omega^2/g$ [1] (the cavity's acceleration amplitude in g)"
                       if xname == "gamma" else t.label(xname))
    axes_legend(axes[2], loc="best")
    save(fig, out_dir, "reduced.png", written, below=None if single else axes[0])
