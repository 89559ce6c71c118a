"""compare.png: compare.csv: the DEM's response against the continuum model's, and the error."""
from .figure import axes_legend, colours, new_figure, readable_log_axis, save
from .tables import groups_by_point, note, read_table, sorted_by_frequency


def plot_compare(directory, out_dir, written):
    t = read_table(directory, "compare.csv")
    if t is None:
        return
    t.require("frequency", "dem_response", "model_response")
    if t.rows == 0:
        note(f"{t.path} has no rows: compare.png not drawn")
        return
    fig, (top, bottom) = new_figure(panels=2, height=6.6, ratios=[2.2, 1])
    groups = groups_by_point(t)
    several = len(groups) > 1
    # One run: a colour per curve. A study: a colour per point, a line style per curve.
    for (label, rows), c in zip(groups, colours(len(groups))):
        rows = sorted_by_frequency(t, rows)
        f = t.num("frequency", rows)
        tag = f" ({label})" if several else ""
        pick = (lambda own: c) if several else (lambda own: own)
        if t.has("bare_response"):
            top.plot(f, t.num("bare_response", rows), color=pick("0.55"), lw=1, alpha=0.5 if several else 0.9,
                     label="bare structure" + tag)
        top.plot(f, t.num("dem_response", rows), "o-", color=pick("C0"), ms=5, lw=1.4, label="DEM (coupled run)" + tag)
        top.plot(f, t.num("model_response", rows), "-", color=pick("C1"), lw=1.6,
                 label=r"linear model with the DEM's $C_b$, $M_b$" + tag)
        if t.has("eq20_response"):
            top.plot(f, t.num("eq20_response", rows), "--", color=pick("C2"), lw=1.4,
                     label="the study's Eq. (20) from e and the impact phase" + tag)
        if t.has("model_error"):
            bottom.plot(f, 100 * t.num("model_error", rows), "o-", color=pick("C1"), ms=4,
                        label=None if several else "linear model")
        if t.has("eq20_error"):
            bottom.plot(f, 100 * t.num("eq20_error", rows), "s--", color=pick("C2"), ms=4,
                        label=None if several else "Eq. (20)")
    top.set_yscale("log")
    readable_log_axis(top)
    top.set_ylabel("response amplitude [m]")
    top.set_title("DEM response against the continuum model's prediction", fontsize=10)
    bottom.axhline(0.0, color="0.3", lw=0.8)
    bottom.set_ylabel("relative error [%]")
    bottom.set_xlabel("frequency [Hz]")
    if several:
        bottom.set_title("relative error: linear model (circles, solid), Eq. (20) (squares, dashed)", fontsize=9)
        save(fig, out_dir, "compare.png", written, below=top)
    else:
        axes_legend(top, loc="best")
        axes_legend(bottom, loc="best")
        save(fig, out_dir, "compare.png", written)
