"""response.png: sweep.csv (+ bare_curve.csv, peaks.csv): the accelerance at the response point with
and without the bag, each peak's reduction."""
import math

import numpy as np

from .figure import axes_legend, colours, db_to_percent, new_figure, readable_log_axis, save
from .tables import BadInput, finite, groups_by_point, has_mean, mean_col, note, read_table, sorted_by_frequency


def accelerance(t, rows, bare=False):
    """|A| [m/s^2/N] of the rows: the table's accelerance, else w^2 |H| from its receptance
    (abs, or re and im). None if the table has neither."""
    p = "bare_" if bare else ""
    if t.has(p + "accelerance_abs"):
        return t.num(p + "accelerance_abs", rows)
    w2 = (2 * math.pi * t.num("frequency", rows)) ** 2
    if t.has(p + "receptance_abs"):
        return w2 * t.num(p + "receptance_abs", rows)
    if t.has(p + "receptance_re") and t.has(p + "receptance_im"):
        return w2 * np.hypot(t.num(p + "receptance_re", rows), t.num(p + "receptance_im", rows))
    return None


def bare_curves(sweep, bare_table):
    """[(label, f, |A|)]: the bare reference from bare_curve.csv, else from the sweep's own bare
    column; one curve when every study point has the same."""
    src = sweep
    if bare_table is not None:
        bare_table.require("frequency")
        if accelerance(bare_table, np.arange(bare_table.rows), bare=True) is None:
            raise BadInput(f"{bare_table.path}: needs 'bare_accelerance_abs [m/s^2/N]' or 'bare_receptance_abs "
                           f"[m/N]'; columns found: {', '.join(bare_table.names())}")
        src = bare_table
    curves = []
    for label, rows in groups_by_point(src):
        rows = sorted_by_frequency(src, rows)
        f, a = src.num("frequency", rows), accelerance(src, rows, bare=True)
        if a is None:
            return []
        keep = finite(f, a)
        curves.append((label, f[keep], a[keep]))
    if not curves:
        return []
    f0, a0 = curves[0][1], curves[0][2]
    if all(len(f) == len(f0) and np.allclose(f, f0) and np.allclose(a, a0, rtol=1e-9) for _, f, a in curves):
        return [("", f0, a0)]
    return curves


def peak_text(t, row):
    """"mode 1: -11.1 dB (72%)": the change of the peak in dB (negative: lowered) and the reduction in %."""
    mode = mean_col(t, "mode", [row])[0] if has_mean(t, "mode") else math.nan
    db = mean_col(t, "reduction_dB", [row])[0]
    pct = mean_col(t, "reduction_percent", [row])[0] if has_mean(t, "reduction_percent") else float(db_to_percent(db))
    name = f"mode {mode:.0f}" if np.isfinite(mode) else f"peak {row + 1}"
    ci = mean_col(t, "reduction_dB_ci95", [row])[0] if has_mean(t, "reduction_dB_ci95") else math.nan
    spread = f" +- {ci:.1f}" if np.isfinite(ci) else ""
    edge = mean_col(t, "at_band_edge", [row])[0] if has_mean(t, "at_band_edge") else 0
    # A peak at the band's edge may lie outside it: its reduction is only a bound.
    warning = "; AT THE BAND'S EDGE" if np.isfinite(edge) and edge > 0 else ""
    return f"{name}: {-db:+.1f}{spread} dB ({pct:.0f}%){warning}"


def annotate_peaks(ax, peaks):
    """An arrow from each mode's bare peak to its damped one, labelled with the reduction."""
    peaks.require("bare_frequency", "bare_peak", "frequency", "peak", "reduction_dB")
    for r in range(peaks.rows):
        fb, hb, fd, hd = (peaks.num(c, [r])[0] for c in ("bare_frequency", "bare_peak", "frequency", "peak"))
        if not np.all(np.isfinite([fb, hb, fd, hd])):
            continue
        ab, ad = (2 * math.pi * fb) ** 2 * hb, (2 * math.pi * fd) ** 2 * hd  # accelerance = w^2 |H|
        ax.plot([fb], [ab], "o", ms=7, mfc="none", mec="0.2", zorder=6)
        ax.plot([fd], [ad], "*", ms=12, color="crimson", zorder=6)
        ax.annotate("", xy=(fd, ad), xytext=(fb, ab),
                    arrowprops=dict(arrowstyle="->", color="crimson", lw=1.2, shrinkA=4, shrinkB=6))
        ax.annotate(peak_text(peaks, r), xy=(max(fb, fd), math.sqrt(ab * ad)), xytext=(10, 0),
                    textcoords="offset points", va="center", fontsize=10, color="crimson",
                    bbox=dict(boxstyle="round,pad=0.25", fc="white", ec="crimson", alpha=0.9))


def plot_response(directory, out_dir, written):
    sweep = read_table(directory, "sweep.csv")
    if sweep is None:
        return
    sweep.require("frequency")
    if accelerance(sweep, np.arange(sweep.rows)) is None:
        raise BadInput(f"{sweep.path}: needs 'accelerance_abs [m/s^2/N]' or 'receptance_re [m/N]' and "
                       f"'receptance_im [m/N]'; columns found: {', '.join(sweep.names())}")
    if sweep.rows == 0:
        note(f"{sweep.path} has no rows yet: response.png not drawn")
        return
    peaks = read_table(directory, "peaks.csv")
    bare = bare_curves(sweep, read_table(directory, "bare_curve.csv"))
    groups = groups_by_point(sweep)
    several = len(groups) > 1
    cols = colours(len(groups))
    fig, (ax,) = new_figure(height=4.8)
    for label, f, a in bare:
        ax.plot(f, a, color="0.35", lw=1.3, ls="-" if len(bare) == 1 else ":",
                label="bare structure" + (f" ({label})" if label else ""))
    # A study's legend carries each point's reductions; a single run's are drawn on the curves.
    peak_rows = dict(groups_by_point(peaks)) if peaks is not None and peaks.is_study() else {}
    loose_labelled = False
    spread = None
    for (label, rows), c in zip(groups, cols):
        rows = sorted_by_frequency(sweep, rows)
        f, a = sweep.num("frequency", rows), accelerance(sweep, rows)
        # Error bars: the 95% interval of |H| over the point's correlated cycles (sweep.csv's
        # receptance_abs_ci95, as |A| = w^2 |H|), else the older tables' cycle-to-cycle spread.
        ci = sweep.opt("receptance_abs_ci95", rows)
        spread = ci * (2 * np.pi * f) ** 2 if ci is not None else None
        if spread is None and sweep.opt("spread", rows) is not None:
            spread = np.abs(sweep.opt("spread", rows)) * a  # spread is relative
        yerr = None
        if spread is not None:
            s = np.nan_to_num(spread)
            yerr = np.vstack([np.minimum(s, 0.9 * a), s])  # kept above zero on the log axis
        name = label or "with the bag"
        if label in peak_rows and has_mean(peaks, "reduction_dB"):
            name += "; " + "; ".join(peak_text(peaks, r) for r in peak_rows[label])
        ax.errorbar(f, a, yerr=yerr, fmt="o-", color=c, ms=4.5, lw=1.4, elinewidth=1, capsize=2.5, label=name)
        steady = sweep.opt("steady", rows)
        if steady is not None and (steady < 0.5).any():
            loose = steady < 0.5
            ax.plot(f[loose], a[loose], "o", ms=8.5, mfc="none", mec="crimson", mew=1.3, zorder=5,
                    label=None if loose_labelled else "not steady (left out of the peak)")
            loose_labelled = True
    if peaks is not None and not peaks.is_study():
        annotate_peaks(ax, peaks)
    ax.set_yscale("log")
    readable_log_axis(ax)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel(r"accelerance $|A|$ [m/s$^2$/N]")
    title = "Frequency response at the response point, with and without the bag"
    if spread is not None:
        title += "\n(error bars: " + ("95% interval over the correlated cycles" if sweep.has("receptance_abs_ci95")
                                      else "cycle-to-cycle spread of the response") + ")"
    ax.set_title(title, fontsize=10)
    if several:
        save(fig, out_dir, "response.png", written, below=ax)
    else:
        axes_legend(ax, loc="best")
        save(fig, out_dir, "response.png", written)
