"""study_<key>.png: a study's peaks.csv (peaks_ensemble.csv if there) and reduced.csv: the peak
reduction and C_b/(M_b w) against each varied case key."""
import os
import re

import numpy as np

from .figure import MODE_LINES, MODE_MARKERS, axes_legend, db_to_percent, new_figure, percent_to_db, plt, save
from .tables import BadInput, err_col, finite, has_mean, mean_col, note, read_table


def key_axis(t, key, rows):
    """(x, categories, label): the key's SI values when every one is a number, else positions of
    its strings in order of first appearance (categories: those strings, else None)."""
    si = [h for n, u, h in t.columns if n == key and u is not None]
    if si:
        x_all = t.numbers[si[0]][t.good_rows()]
        if len(x_all) and np.all(np.isfinite(x_all)):
            return t.numbers[si[0]][rows], None, si[0]
    categories = list(dict.fromkeys(t.text(key, t.good_rows())))
    return np.array([categories.index(v) for v in t.text(key, rows)], dtype=float), categories, key


def split_series(t, key, rows, modes):
    """[(mode, others, positions)]: the table rows `rows` (positions into it) split by mode (`modes`,
    aligned with rows, or None) and by the values of the other varied keys. The others are not split
    on when they were varied together with `key` (a zip: one row per split)."""
    others = [k for k in t.varied_keys() if k != key]
    texts = [t.text(k, rows) for k in others]

    def split(with_others):
        out = {}
        for j in range(len(rows)):
            o = tuple((k.split(".")[-1], tx[j]) for k, tx in zip(others, texts)) if with_others else ()
            out.setdefault((None if modes is None else float(modes[j]), o), []).append(j)
        return out

    series = split(True)
    if others and all(len(v) == 1 for v in series.values()):
        series = split(False)
    return [(m, o, np.array(v, dtype=int)) for (m, o), v in series.items()]


class Styles:
    """One look per series across a figure's panels: with other varied keys, a colour per
    combination of them and a marker and line style per mode; else a colour per mode."""

    def __init__(self, by_others):
        self.by_others = by_others
        self.colour_index, self.mode_index = {}, {}
        self.cycle = plt().rcParams["axes.prop_cycle"].by_key()["color"]

    def __call__(self, mode, others):
        mi = self.mode_index.setdefault(mode, len(self.mode_index))
        if not self.by_others:
            return self.cycle[mi % len(self.cycle)], "o", "-"
        ci = self.colour_index.setdefault(others, len(self.colour_index))
        return self.cycle[ci % len(self.cycle)], MODE_MARKERS[mi % len(MODE_MARKERS)], MODE_LINES[mi % len(MODE_LINES)]


def series_label(mode, others):
    parts = ([f"mode {mode:g}"] if mode is not None and np.isfinite(mode) else []) + [f"{k} = {v}" for k, v in others]
    return ", ".join(parts) or None


def draw_series(ax, t, key, rows, y, err, style, label):
    x, _, _ = key_axis(t, key, rows)
    order = np.argsort(x, kind="stable")
    x, y = x[order], y[order]
    err = None if err is None else np.nan_to_num(np.abs(err[order]))
    keep = finite(x, y)
    colour, marker, line = style
    ax.errorbar(x[keep], y[keep], yerr=None if err is None else err[keep], fmt=marker, ls=line, color=colour, ms=6,
                lw=1.5, elinewidth=1.1, capsize=3, label=label)


def study_table(directory, name):
    t = read_table(directory, name)
    return t if t is not None and t.is_study() else None


def peak_modes(peaks, rows):
    return mean_col(peaks, "mode", rows) if has_mean(peaks, "mode") else None


def cb_rows(reduced, peaks):
    """The rows of `reduced` to put against the varied keys, and each one's mode (or None): one row
    per point as it is; for a coupled sweep (several rows per point) the row nearest each mode's
    damped peak frequency in `peaks`. None (with a note) when it cannot choose."""
    rows = reduced.good_rows()
    by_point = {}
    for i, k in zip(rows, reduced.point_keys(rows)):
        by_point.setdefault(k, []).append(i)
    if all(len(v) == 1 for v in by_point.values()):
        return np.array([v[0] for v in by_point.values()], dtype=int), None, False
    if peaks is None or not has_mean(reduced, "frequency") or not has_mean(peaks, "frequency"):
        note(f"{reduced.path}: several rows per point and no peaks.csv (with frequencies) to choose each "
             "mode's row: C_b/(M_b w) left out of the study figures")
        return None
    f_red = mean_col(reduced, "frequency")
    prows = peaks.good_rows()
    modes = peak_modes(peaks, prows)
    chosen, chosen_modes = [], []
    for j, (i, k) in enumerate(zip(prows, peaks.point_keys(prows))):
        f_peak = mean_col(peaks, "frequency", [i])[0]
        if k in by_point and np.isfinite(f_peak):
            candidates = np.array(by_point[k])
            chosen.append(candidates[np.argmin(np.abs(f_red[candidates] - f_peak))])
            chosen_modes.append(None if modes is None else modes[j])
    if not chosen:
        note(f"{reduced.path}: no point matches a row of {peaks.path}: C_b/(M_b w) left out of the study figures")
        return None
    return np.array(chosen, dtype=int), None if modes is None else np.array(chosen_modes), True


def plot_study(directory, out_dir, written):
    if os.path.isfile(os.path.join(directory, "trade.csv")):
        return  # a trade's runs vary fidelity settings, not a case key: trade.png shows them
    single, ensemble = study_table(directory, "peaks.csv"), study_table(directory, "peaks_ensemble.csv")
    peaks = ensemble if ensemble is not None else single
    red_single, red_ensemble = study_table(directory, "reduced.csv"), study_table(directory, "reduced_ensemble.csv")
    # C_b/(M_b w): ensembles with ensembles, single runs with single runs.
    reduced, cb_peaks = (red_ensemble, ensemble) if red_ensemble is not None and ensemble is not None \
        else (red_single, single)
    if peaks is None and reduced is None:
        return
    if peaks is not None and not has_mean(peaks, "reduction_dB"):
        peaks.require("reduction_dB")
    cb = None
    if reduced is not None:
        if not has_mean(reduced, "Cb_over_Mbw"):
            reduced.require("Cb_over_Mbw")
        cb = cb_rows(reduced, cb_peaks)
    main_table = peaks if peaks is not None else reduced
    keys = main_table.varied_keys()
    if not keys:
        raise BadInput(f"{main_table.path}: a study's table has its varied keys as columns (e.g. "
                       "'bag.balls.diameter'); none found")
    for key in keys:
        panels = []  # (kind, table, rows, each row's mode or None, y, error bars or None)
        if peaks is not None:
            rows = peaks.good_rows()
            panels.append(("peaks", peaks, rows, peak_modes(peaks, rows), mean_col(peaks, "reduction_dB", rows),
                           err_col(peaks, "reduction_dB", rows) if peaks is ensemble else None))
        if cb is not None:
            rows, modes, _ = cb
            panels.append(("cb", reduced, rows, modes, mean_col(reduced, "Cb_over_Mbw", rows),
                           err_col(reduced, "Cb_over_Mbw", rows)))
        fig, axes = new_figure(panels=len(panels), height=4.4 if len(panels) == 1 else 7.6)
        split = [split_series(t, key, rows, modes) for _, t, rows, modes, _, _ in panels]
        styles = Styles(any(o for s in split for _, o, _ in s))
        for ax, (kind, t, rows, modes, y, err), series in zip(axes, panels, split):
            for mode, others, idx in series:
                style = styles(mode, others)
                draw_series(ax, t, key, rows[idx], y[idx], None if err is None else err[idx], style,
                            series_label(mode, others))
                if kind == "peaks" and peaks is ensemble and single is not None:
                    draw_single_runs(ax, single, key, mode, others, style)
            x, categories, label = key_axis(t, key, t.good_rows())
            if categories is not None:
                ax.set_xticks(range(len(categories)))
                ax.set_xticklabels(categories)
                ax.set_xlim(-0.5, len(categories) - 0.5)
            elif len(np.unique(x)) <= 12:
                ax.set_xticks(np.unique(x))
            axes[-1].set_xlabel(label)
            others = [k for k in t.varied_keys() if k != key]
            with_it = f"; {', '.join(others)} varied with it" if others and not any(o for _, o, _ in series) else ""
            if kind == "peaks":
                ax.axhline(0.0, color="0.3", lw=0.8)
                ax.set_ylabel("peak reduction [dB]")
                ax.secondary_yaxis("right", functions=(db_to_percent, percent_to_db)).set_ylabel("peak reduction [%]")
                what = "mean over the seeds, error bars: standard error" if peaks is ensemble else "each run"
                ax.set_title(f"Peak reduction against {key} ({what}{with_it})", fontsize=10)
            else:
                ax.set_ylabel(r"$C_b/(M_b\,\omega)$ [1]")
                title = rf"$C_b/(M_b\,\omega)$ against {key} (error bars: standard error{with_it})"
                if cb[2]:
                    title += "\ncoupled sweep: the row nearest each mode's damped peak frequency"
                ax.set_title(title, fontsize=10)
        many = sum(len(s) for s in split) > 8
        if not many:
            for ax in axes:
                axes_legend(ax, loc="best")
        save(fig, out_dir, f"study_{re.sub(r'[^A-Za-z0-9._-]+', '_', key)}.png", written,
             below=axes if many else None)


def draw_single_runs(ax, single, key, mode, others, style):
    """The single runs behind an ensemble's series (same mode and other keys), small and faint."""
    rows = single.good_rows()
    if not single.has("reduction_dB") or not len(rows):
        return
    for m, o, idx in split_series(single, key, rows, peak_modes(single, rows)):
        if o == others and m == mode:
            x, _, _ = key_axis(single, key, rows[idx])
            ax.plot(x, single.num("reduction_dB", rows[idx]), style[1], color=style[0], ms=3.5, alpha=0.35, mec="none")
