#!/usr/bin/env python3
# The work of tools/validate-study (which installs and builds, then runs this): the source study's
# three studies reproduced at its calibrated level, modes 1 and 3, from scratch
# (docs/validation/README.md has the results and the run time):
#   1. the pipe's damping ratio calibrated on the study's Table 3 (5% of 4-mm balls at mid-span:
#      mode 1 14.9 dB, mode 3 14.5 dB) at the force amplitude --amplitude (default 0.04 N, the force
#      of the largest mode-1 reduction at the case's damping: docs/validation/README.md, section 1):
#      `bagdem calibrate cases/pipe-beanbag --key primary.damping_ratio`, both modes fitted by least
#      squares, --seeds per value (skipped with --damping-ratio);
#   2. the three studies of cases/studies (ball size, mass ratio, position) at that level, modes 1
#      and 3, --seeds per point (`bagdem sweep`, resumable: run the command again after a stop);
#   3. docs/validation/study.csv (one row per point and mode) and the figures study_<study>.png;
#      continuum.csv (the continuum models against the DEM, per point and mode) and
#      continuum-summary.csv (per study, mode and model); the clearance
#      study (cases/studies/clearance) and clearance.csv, and bag radii 7-11 mm, mode 1, at
#      --clearance-amplitude (default 0.5 N, where d/X comes down to 1.5-8) and clearance-force.csv;
#      claims.csv (the study's claims judged on
#      the intervals; the impact claim also at --impact-amplitude, default 0.2 N, where the base
#      case's bag and cases/pipe-slug leave the wall); the calibration as calibrate-modes13.csv, calibration-modes13.json and
#      calibrate-modes13.png;
#   4. with --keys, where the DEM and the study part ways: each candidate key (KEYS) varied alone at
#      Table 3's configuration with the same --seeds starts as the calibrated case, and keys.csv
#      (each value's reduction per mode and its change paired start by start);
#   5. with --slope, what sets the slope of the mass-ratio trend: the mass-ratio study's 5, 8 and 12%
#      at the calibrated level, and again with each model choice of SLOPE_CHOICES varied alone
#      (--seeds starts each), and slope.csv (per choice, value and mode: the reduction at each ratio,
#      the slopes 8 - 5% and 12 - 8% with their intervals, and the runs' mean wall time).
#      --slope alone skips steps 1-4 (it needs --damping-ratio); --slope-choices runs only those named
#      (base, tightness, force, ball-stiffness, bag-radius, film-thickness, bag-length, bore-friction, tight-bag), slope.csv and slope-seeds.csv
#      (each start's figure) are written after each;
#   6. with --table3, the pipe's damping ratio fitted by least squares to all 20 figures of Table 3
#      at once (cases/studies/mass-ratio/table3.csv: modes 1 and 3 at 5-14%, the mass-ratio study's
#      bag), at the force --amplitude: calibrate-table3.csv and calibration-table3.json (each
#      figure's residual, the mean absolute residual per mode). --table3 alone skips steps 1-5.
#   7. with --table3-maps, the same 20 figures fitted on effective-field maps (bagdem calibrate
#      --maps): a map of the study's bag at each of Table 3's mass ratios (bagdem characterize, in
#      OUT/table3-maps/ratio-R, resumable), then the force and one damping ratio for all modes, and
#      the force and a damping ratio per mode (primary.damping_ratio@1, @3), each fitted to all 20:
#      calibrate-table3-maps{,-permode}.csv and calibration-table3-maps{,-permode}.json. Alone, it
#      skips steps 1-6.
#
#   8. with --table3-check, Table 3 by coupled DEM at the keys given (--amplitude, --damping-ratio; mode 3 at
#      --damping-ratio3, default the same), each mode its own sweep of the mass-ratio study (OUT/table3-check/mode-M),
#      and table3-check.csv (each figure: the DEM's mean and 95% half-width, the residual) and
#      table3-check-summary.csv (per mode: the MAE, the largest and the mean residual). Alone, it skips steps 1-7.
#
#   tools/validate-study [--amplitude "0.04 N"] [--damping-ratio Z] [--seeds 3] [--out DIR]
#                        [--docs DIR] [--jobs J] [--keys] [--impact-amplitude "0.2 N"]
#                        [--clearance-amplitude "0.5 N"] [--slope [--slope-choices C,...]] [--table3] [--table3-maps]
#                        [--table3-check [--damping-ratio3 Z3] [--table3-modes 1,3]]
#
# study.csv's columns: study (ball-size, mass-ratio, position), param (ball_diameter_mm,
# mass_ratio_pct, position_xL), value (in those units), `mode [1]`, `reduction_db_mean [dB]`,
# `reduction_db_ci95 [dB]` (the half-width over the seeds), `seeds [1]` (the seeds done), and
# `mass_ratio_actual [1]` (whole balls: the ratio the point simulated, reduced.csv's mass_ratio).
# Exit codes: 0 every step done, 1 a command or a file failed (its message says which).
import csv
import json
import math
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
BAGDEM = os.path.join(os.environ.get("BAGDEM_BUILD_DIR", os.path.join(ROOT, "build")), "bagdem")
PIPE_LENGTH = 1.39  # m, cases/pipe-beanbag's primary.length: positions are given as x/L
TABLE3 = [(1, 14.9), (3, 14.5)]  # the study's Table 3: mode, peak reduction [dB] (5% of 4-mm balls, mid-span)
MODES = ['excitation.around_modes=[1, 3]', 'output.cavity_interval="0.05 ms"']  # mode 3 (508 Hz) sampled 40 times a period
STUDIES = [  # name, study directory, param, its value from the varied key's SI value
    ("ball-size", "cases/studies/ball-size", "ball_diameter_mm", lambda si: 1e3 * si),
    ("mass-ratio", "cases/studies/mass-ratio", "mass_ratio_pct", lambda si: 100 * si),
    ("position", "cases/studies/position", "position_xL", lambda si: si / PIPE_LENGTH),
]
# Step 4's candidates: (what is varied, its directory, the --vary arguments; {zeta} is the
# calibrated damping ratio). The mode-3 damping ratio replaces the level's one ratio for all modes.
CLEARANCE_FORCE_RADII = (7, 8, 9, 10, 10.5, 11)  # mm: d/X about 8 down to 1.5 at 0.5 N
KEYS = [
    ("interactions.steel-ldpe.restitution", "film-restitution", ["--vary", "interactions.steel-ldpe.restitution=0.1,0.6"]),
    ("interactions.steel-ldpe.friction", "film-friction", ["--vary", "interactions.steel-ldpe.friction=0.2,0.8"]),
    ("materials.ldpe.youngs_modulus", "film-stiffness", ["--vary", 'materials.ldpe.youngs_modulus="0.1 GPa","0.6 GPa"']),
    ("bag.strings.0.stiffness and bag.strings.1.stiffness", "strings",
     ["--vary", 'bag.strings.0.stiffness="50 N/m","800 N/m"', "--vary", 'bag.strings.1.stiffness="50 N/m","800 N/m"', "--zip"]),
    ("primary.damping_ratio", "mode3-damping", ["--vary", "primary.damping_ratio=[{zeta}, {zeta}, 0.0049]"]),
]


def run(args):
    """Runs a bagdem sweep or ensemble; exit 3 (some points failed: their messages are in the sweep's output) is
    reported and the study's table keeps those points as failed rows."""
    print("+ " + " ".join(args), flush=True)
    code = subprocess.call(args)
    if code == 3:
        print(f"tools/validate-study: some points of `{args[2]}` failed; their rows say so (seeds 0)", flush=True)
    elif code != 0:
        sys.exit(f"tools/validate-study: `{' '.join(args)}` exited {code}")


def key_column(header):
    """The varied key's column in SI units of a study's table: "bag.balls.diameter [m]"."""
    return next((c for c in header if " [" in c and "." in c.split(" [")[0]), None)


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def run_calibration(cal, amplitude, seeds, jobs, targets, sets):
    """bagdem calibrate of the pipe's damping ratio at the force `amplitude` into `cal`, with the
    target arguments `targets` and the overrides `sets`; its calibration.json."""
    args = [BAGDEM, "calibrate", os.path.join(ROOT, "cases/pipe-beanbag"), "--key", "primary.damping_ratio",
            "--bounds", "0.002,0.006", "--scan", "5", "--rounds", "3", "--seeds", str(seeds), "--out", cal,
            "--jobs", str(jobs)]
    for m in sets + [f'excitation.amplitude="{amplitude}"'] + MODES:
        args += ["--set", m]
    args += targets
    print("+ " + " ".join(args), flush=True)
    code = subprocess.call(args)
    if code not in (0, 3):  # 3: not every target matched: the least-squares value stands, with its residuals
        sys.exit(f"tools/validate-study: the calibration exited {code}")
    with open(os.path.join(cal, "calibration.json")) as f:
        return json.load(f)


def calibrate_table3(out, amplitude, seeds, jobs, docs):
    """Step 6: the damping ratio on all of Table 3 (bagdem calibrate --targets), its tables into docs."""
    cal = os.path.join(out, "calibrate-table3")
    run_calibration(cal, amplitude, seeds, jobs, ["--targets", os.path.join(ROOT, "cases/studies/mass-ratio/table3.csv")],
                    rows_of_set(os.path.join(ROOT, "cases/studies/mass-ratio/study.toml")))
    for name in ("calibration.json", "calibrate.csv"):
        stem, ext = os.path.splitext(name)
        shutil.copy(os.path.join(cal, name), os.path.join(docs, f"{stem}-table3{ext}"))


def table3_check(out, amplitude, zetas, seeds, jobs, docs):
    """Step 8: Table 3 by coupled DEM at given keys (the force --amplitude; a damping ratio per mode, `zetas`
    {mode: ratio}), each mode its own sweep of the mass-ratio study; table3-check.csv (per figure the DEM's mean and
    95% half-width over the starts, the residual) and table3-check-summary.csv (per mode the MAE and the largest
    residual), both also printed."""
    table3 = rows(os.path.join(ROOT, "cases/studies/mass-ratio/table3.csv"))
    figures, summary = [], []
    for mode, zeta in sorted(zetas.items()):
        d = os.path.join(out, "table3-check", f"mode-{mode}")
        sets = [f"excitation.around_modes=[{mode}]", f'excitation.amplitude="{amplitude}"', f"primary.damping_ratio={zeta}"]
        if mode != 1:
            sets.append('output.cavity_interval="0.05 ms"')  # mode 3 (508 Hz) sampled 40 times a period
        args = [BAGDEM, "sweep", os.path.join(ROOT, "cases/studies/mass-ratio"), "--seeds", str(seeds), "--jobs", str(jobs), "--out", d]
        for m in sets:
            args += ["--set", m]
        run(args)
        dem = {float(value): per for (value, m), per in by_seed(d).items() if m == mode}
        residuals = []
        for t in (t for t in table3 if int(t["mode"]) == mode):
            ratio, target = float(t["bag.balls.mass_ratio"]), float(t["reduction_db"])
            m, h = mean_ci95(list(dem.get(ratio, {}).values()))
            residuals.append(m - target)
            figures.append({"mode [1]": mode, "mass_ratio [1]": f"{ratio:g}", "target_db [dB]": f"{target:g}", "reduction_db_mean [dB]": f"{m:.2f}",
                            "reduction_db_ci95 [dB]": f"{h:.2f}", "seeds [1]": len(dem.get(ratio, {})), "residual_db [dB]": f"{m - target:+.2f}"})
        done = [r for r in residuals if math.isfinite(r)]
        mae = sum(abs(r) for r in done) / len(done) if done else math.nan
        summary.append({"mode [1]": mode, "amplitude": amplitude, "damping_ratio [1]": zeta, "figures [1]": len(done),
                        "mae_db [dB]": f"{mae:.2f}", "max_abs_residual_db [dB]": f"{max(map(abs, done)):.2f}" if done else "nan",
                        "mean_residual_db [dB]": f"{sum(done) / len(done):+.2f}" if done else "nan"})
        print(f"Table 3, mode {mode} at {amplitude}, damping ratio {zeta}: MAE {mae:.2f} dB over {len(done)} figures", flush=True)
    # The modes not run now keep their rows of the files there (--table3-modes runs some of them).
    for name, table in (("table3-check.csv", figures), ("table3-check-summary.csv", summary)):
        path = os.path.join(docs, name)
        kept = [r for r in rows(path) if int(r["mode [1]"]) not in zetas] if os.path.exists(path) else []
        merged = sorted(kept + table, key=lambda r: int(r["mode [1]"]))
        write_csv(path, list(table[0].keys()), merged)


TABLE3_MAP = ["--gamma", "0.01,20", "--amplitudes", "6", "--frequencies", "4"]  # design's default grid, down to Gamma 0.01


def calibrate_table3_maps(out, seeds, jobs, docs):
    """Step 7: a map per mass ratio of Table 3, then bagdem calibrate --maps on all 20 figures: the force with one damping
    ratio, and with one per mode."""
    table3 = os.path.join(ROOT, "cases/studies/mass-ratio/table3.csv")
    case = os.path.join(ROOT, "cases/pipe-beanbag")
    sets = rows_of_set(os.path.join(ROOT, "cases/studies/mass-ratio/study.toml")) + MODES
    ratios = sorted({r["bag.balls.mass_ratio"] for r in rows(table3)}, key=float)
    maps = []
    for r in ratios:
        d = os.path.join(out, "table3-maps", f"ratio-{r}")
        args = [BAGDEM, "characterize", case, "--seeds", str(seeds), "--jobs", str(jobs), "--out", d] + TABLE3_MAP
        for m in sets + [f"bag.balls.mass_ratio={r}"]:
            args += ["--set", m]
        run(args)
        maps.append(d)
    fits = [("", ["--key", "excitation.amplitude", "--key", "primary.damping_ratio", "--bounds", '"0.01 N","0.2 N"', "--bounds", "0.001,0.02"]),
            ("-permode", ["--key", "excitation.amplitude", "--key", "primary.damping_ratio@1", "--key", "primary.damping_ratio@3",
                          "--bounds", '"0.01 N","0.2 N"', "--bounds", "0.001,0.02", "--bounds", "0.001,0.02"])]
    for tag, keys in fits:
        cal = os.path.join(out, f"calibrate-table3-maps{tag}")
        args = [BAGDEM, "calibrate", case, "--targets", table3, "--out", cal, "--maps"] + maps + keys
        for m in sets:
            args += ["--set", m]
        print("+ " + " ".join(args), flush=True)
        if subprocess.call(args) != 0:
            sys.exit(f"tools/validate-study: the calibration on maps{tag} failed")
        for name in ("calibration.json", "calibrate.csv"):
            stem, ext = os.path.splitext(name)
            shutil.copy(os.path.join(cal, name), os.path.join(docs, f"{stem}-table3-maps{tag}{ext}"))


def calibrate(out, amplitude, seeds, jobs):
    """The pipe's damping ratio at the given force: both Table 3 modes by least squares."""
    cal = os.path.join(out, "calibrate")
    targets = []
    for mode, db in TABLE3:
        targets += ["--target", f"mode={mode},reduction_db={db}"]
    doc = run_calibration(cal, amplitude, seeds, jobs, targets, ["bag.balls.mass_ratio=0.05"])
    if not doc["solutions"]:
        sys.exit(f"tools/validate-study: the calibration found no damping ratio: {doc['note']}")
    return cal, doc["solutions"][0]["value_text"]


def study_rows(name, out, param, convert):
    """study.csv's rows of one study: peaks_ensemble.csv per point and mode, the actual mass ratio
    from reduced_ensemble.csv (the same for every frequency of a point)."""
    peaks = rows(os.path.join(out, "peaks_ensemble.csv"))
    reduced = rows(os.path.join(out, "reduced_ensemble.csv"))
    key = key_column(peaks[0])
    ratio = {r[key]: r["mass_ratio_mean [1]"] for r in reduced}
    out_rows = []
    for r in peaks:
        si = float(r[key])
        row = {"study": name, "param": param, "value": f"{convert(si):.6g}", "mode [1]": "", "reduction_db_mean [dB]": "nan",
               "reduction_db_ci95 [dB]": "nan", "seeds [1]": r["n"], "mass_ratio_actual [1]": ratio.get(r[key], "nan")}
        if int(r["n"]) == 0:  # every start of the point failed: a row per mode, empty
            out_rows += [dict(row, **{"mode [1]": str(mode)}) for mode, _ in TABLE3]
            continue
        out_rows.append(dict(row, **{"mode [1]": f"{float(r['mode_mean [1]']):g}", "reduction_db_mean [dB]": r["reduction_dB_mean [dB]"],
                                     "reduction_db_ci95 [dB]": r["reduction_dB_ci95 [dB]"]}))
    return out_rows


CONTINUUM = [("modal", "model_response [m]"), ("eq7", "eq7_response [m]"), ("eq20", "eq20_response [m]")]


def mean_ci95(values):
    """Mean and the 95% half-width over the seeds (Student t), NaN for fewer than 2."""
    v = [x for x in values if math.isfinite(x)]
    if not v:
        return math.nan, math.nan
    m = sum(v) / len(v)
    if len(v) < 2:
        return m, math.nan
    t95 = {2: 12.706, 3: 4.303, 4: 3.182, 5: 2.776, 6: 2.571, 7: 2.447, 8: 2.365, 9: 2.306, 10: 2.262}.get(len(v), 2.0)
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1))
    return m, t95 * sd / math.sqrt(len(v))


def finished(out):
    """The rows of a study's peaks.csv whose run finished, each with the varied key's SI value (0 for
    a study of one configuration), its mode, and its point's directory."""
    peaks = rows(os.path.join(out, "peaks.csv"))
    key = key_column(peaks[0]) if peaks else None
    for r in peaks:
        if r["status"] == "done":
            yield float(r[key]) if key else 0.0, int(float(r["mode [1]"])), r, os.path.join(out, f"point-{int(r['point']):03d}")


def continuum_rows(name, out, param, convert):
    """continuum.csv's rows of one study: per point and mode, each continuum model's peak reduction
    less the DEM's (from each start's compare.csv: the models fed the DEM's C_b, M_b and e at every
    frequency; 20 log10 of the DEM's largest response over the model's), mean and 95% half-width over
    the starts, and the median |relative error| of the response over all frequencies and starts."""
    groups = {}
    for si, mode, r, point in finished(out):
        value = convert(si)
        cmp = [c for c in rows(os.path.join(point, "compare.csv")) if int(float(c["mode [1]"])) == mode]
        if not cmp:
            continue
        g = groups.setdefault((value, mode), {"dem": [], "errors": {m: [] for m, _ in CONTINUUM}, "diff": {m: [] for m, _ in CONTINUUM}})
        g["dem"].append(float(r["reduction_dB [dB]"]))
        dem_peak = max(float(c["dem_response [m]"]) for c in cmp)
        for model, column in CONTINUUM:
            model_peak = max(float(c[column]) for c in cmp)
            g["diff"][model].append(20 * math.log10(dem_peak / model_peak) if model_peak > 0 else math.nan)
            g["errors"][model] += [abs(float(c[column.replace("_response [m]", "_error [1]")])) for c in cmp]
    out_rows = []
    for (value, mode), g in sorted(groups.items()):
        row = {"study": name, "param": param, "value": f"{value:.6g}", "mode [1]": mode, "seeds [1]": len(g["dem"]),
               "dem_reduction_db_mean [dB]": f"{mean_ci95(g['dem'])[0]:.4g}"}
        for model, _ in CONTINUUM:
            m, h = mean_ci95(g["diff"][model])
            e = sorted(g["errors"][model])
            row[f"{model}_minus_dem_db_mean [dB]"] = f"{m:.4g}"
            row[f"{model}_minus_dem_db_ci95 [dB]"] = f"{h:.3g}"
            row[f"{model}_median_abs_error [1]"] = f"{e[len(e) // 2]:.3g}" if e else "nan"
        out_rows.append(row)
    return out_rows


def continuum_summary(continuum):
    """continuum-summary.csv: per study, mode and model, over the study's points: the mean and the
    largest |model - DEM| of the peak reduction, and the median of the points' median |relative
    error| of the response (NaN points, where a model had no e, left out)."""
    out = []
    for name in sorted({r["study"] for r in continuum}):
        for mode in (1, 3):
            sel = [r for r in continuum if r["study"] == name and int(r["mode [1]"]) == mode]
            for model, _ in CONTINUUM:
                d = [float(r[f"{model}_minus_dem_db_mean [dB]"]) for r in sel]
                d = [x for x in d if math.isfinite(x)]
                e = sorted(x for x in (float(r[f"{model}_median_abs_error [1]"]) for r in sel) if math.isfinite(x))
                out.append({"study": name, "mode [1]": mode, "model": model, "points [1]": len(d),
                            "mean_minus_dem_db [dB]": f"{sum(d) / len(d):.3g}" if d else "nan",
                            "max_abs_minus_dem_db [dB]": f"{max(abs(x) for x in d):.3g}" if d else "nan",
                            "median_abs_error [1]": f"{e[len(e) // 2]:.3g}" if e else "nan"})
    return out


# Step 5's model choices, each varied alone on the mass-ratio study at SLOPE_RATIOS (issue 49): (the
# key, its directory, the --vary arguments). The base values: bag.fill_fraction 0.5, the steel's
# 2 GPa, the bag's 9-mm radius (its length follows the fill), a 50-um LDPE film, the level's force.
SLOPE_RATIOS = (0.05, 0.08, 0.12)
SLOPE_CHOICES = [  # run in this order (the likeliest first)
    ("bag.fill_fraction", "tightness", ["--vary", "bag.fill_fraction=0.65"]),
    ("excitation.amplitude", "force", ["--vary", 'excitation.amplitude="0.03 N","0.05 N"']),
    ("materials.steel.youngs_modulus", "ball-stiffness", ["--vary", 'materials.steel.youngs_modulus="20 GPa"']),
    ("bag.radius", "bag-radius", ["--vary", 'bag.radius="8.5 mm","10.5 mm"']),  # at 8 mm the 12% bag is longer than the 80-mm bore section
    ("bag.film.thickness", "film-thickness", ["--vary", 'bag.film.thickness="100 um"']),
    # One bag for every ratio (the shortest that holds the 12% lattice at every start): it tightens as it
    # fills, fill fraction 0.15 at 5%, 0.25 at 8%, 0.37 at 12%, where the base's bag grows to keep 0.39.
    ("bag.length", "bag-length", ["--vary", 'bag.length="64 mm"']),
    # The film on the bore: below Gamma about 1 (mode 1's damped peak past 9% at the Table 3 fit) a bag
    # that grips the bore rides with it; LDPE on aluminium is about 0.2-0.5, the case 0.4.
    ("interactions.ldpe-aluminium.friction", "bore-friction", ["--vary", "interactions.ldpe-aluminium.friction=0.2,0.8"]),
    # A bag pulled tight: the film's unstretched size 0.9 of the lattice's bag (fill 0.54 where the
    # lattice leaves 0.39), so it closes on the balls as they settle (docs/bag.md, "Tight bags").
    ("bag.film.shrink", "tight-bag", ["--vary", "bag.film.shrink=0.9"]),
]


def per_seed(out):
    """{(the varied key's SI value, mode): [(peak reduction [dB], reduced.csv's row nearest the damped peak)]}
    over the starts done of a study."""
    groups = {}
    for si, mode, r, point in finished(out):
        f = float(r["frequency [Hz]"])
        near = min(rows(os.path.join(point, "reduced.csv")), key=lambda q: abs(float(q["frequency [Hz]"]) - f))
        groups.setdefault((si, mode), []).append((float(r["reduction_dB [dB]"]), near))
    return groups


def by_seed(out):
    """{(the varied values as written, mode): {seed: peak reduction [dB]}} over a study's finished runs."""
    table = rows(os.path.join(out, "peaks.csv"))
    varied = [c for c in (table[0] if table else {}) if " [" not in c and c not in ("point", "status", "seed")]
    groups = {}
    for r in table:
        if r["status"] == "done":
            groups.setdefault((" / ".join(r[c] for c in varied), int(float(r["mode [1]"]))), {})[int(r["seed"])] = float(r["reduction_dB [dB]"])
    return groups


def keys(out, level, zeta, seeds, jobs):
    """keys.csv's rows: the calibrated case (Table 3's configuration at the level) and each KEYS
    variation, per mode the reduction over the starts and its change paired start by start."""
    config = ["bag.balls.mass_ratio=0.05", level[0]] + MODES
    base_dir = os.path.join(out, "keys", "base")
    args = [BAGDEM, "run", os.path.join(ROOT, "cases/pipe-beanbag"), "--seeds", str(seeds), "--out", base_dir]
    for m in config + [level[1]]:
        args += ["--set", m]
    run(args)
    base = {mode: per for (_, mode), per in by_seed(base_dir).items()}
    table = []
    for mode, per in sorted(base.items()):
        m, h = mean_ci95(list(per.values()))
        table.append({"key": "(the calibrated case)", "value": "", "mode [1]": mode, "reduction_db_mean [dB]": f"{m:.2f}",
                      "reduction_db_ci95 [dB]": f"{h:.2f}", "paired_change_db_mean [dB]": "0", "paired_change_db_ci95 [dB]": "0",
                      "seeds [1]": len(per)})
    for key, name, vary in KEYS:
        d = os.path.join(out, "keys", name)
        args = [BAGDEM, "sweep", os.path.join(ROOT, "cases/pipe-beanbag"), "--seeds", str(seeds), "--out", d, "--jobs", str(jobs)]
        for m in config + ([] if key == "primary.damping_ratio" else [level[1]]):
            args += ["--set", m]
        run(args + [v.format(zeta=zeta) for v in vary])
        for (value, mode), per in by_seed(d).items():
            m, h = mean_ci95(list(per.values()))
            dm, dh = mean_ci95([per[k] - base[mode][k] for k in per if k in base.get(mode, {})])
            table.append({"key": key, "value": value, "mode [1]": mode, "reduction_db_mean [dB]": f"{m:.2f}",
                          "reduction_db_ci95 [dB]": f"{h:.2f}", "paired_change_db_mean [dB]": f"{dm:.2f}",
                          "paired_change_db_ci95 [dB]": f"{dh:.2f}", "seeds [1]": len(per)})
    return table


def slope_rows(out, level, seeds, jobs, chosen, done):
    """slope.csv's rows: the calibrated case ("base") and each SLOPE_CHOICES value, per mode the
    reduction at each of SLOPE_RATIOS over the starts, the slopes between them (the per-start
    differences' mean and 95% half-width) and the runs' mean wall time [s]. Runs the choices named in
    `chosen` (all when None) and tabulates every choice whose runs are in OUT; done(table, seeds)
    is called after each choice with the rows so far and the per-start rows (slope-seeds.csv's)."""
    study = rows_of_set(os.path.join(ROOT, "cases/studies/mass-ratio/study.toml"))
    ratios = "bag.balls.mass_ratio=" + ",".join(f"{r:g}" for r in SLOPE_RATIOS)
    table, per_start = [], []
    for key, name, vary in [("(the calibrated case)", "base", [])] + SLOPE_CHOICES:
        d = os.path.join(out, "slope", name)
        args = [BAGDEM, "sweep", os.path.join(ROOT, "cases/pipe-beanbag"), "--seeds", str(seeds), "--out", d, "--jobs", str(jobs),
                "--vary", ratios] + vary
        for m in study + (level if key != "excitation.amplitude" else level[1:]) + MODES:
            args += ["--set", m]
        if chosen is None or name in chosen:
            run(args)
        elif not os.path.exists(os.path.join(d, "peaks.csv")):
            continue
        peaks = [r for r in rows(os.path.join(d, "peaks.csv")) if r["status"] == "done" and r["reduction_dB [dB]"] != ""]
        varied = [c for c in (peaks[0] if peaks else {}) if " [" not in c and c not in ("point", "status", "seed", "bag.balls.mass_ratio")]
        walls = {}  # value -> {point: wall time [s]}
        groups = {}  # (value, mode) -> {ratio: {seed: dB}}
        for r in peaks:
            value = " / ".join(r[c] for c in varied)
            if r["point"] not in walls.setdefault(value, {}):
                with open(os.path.join(d, f"point-{int(r['point']):03d}", "summary.json")) as f:
                    walls[value][r["point"]] = json.load(f)["wall_time_s"]
            g = groups.setdefault((value, int(float(r["mode [1]"]))), {})
            g.setdefault(float(r["bag.balls.mass_ratio"]), {})[int(r["seed"])] = float(r["reduction_dB [dB]"])
            per_start.append({"key": key, "value": value, "mode [1]": r["mode [1]"], "mass_ratio [1]": r["bag.balls.mass_ratio"],
                              "seed": r["seed"], "reduction_dB [dB]": r["reduction_dB [dB]"],
                              "wall_s [s]": f"{walls[value][r['point']]:.1f}"})
        for (value, mode), g in sorted(groups.items()):
            row = {"key": key, "value": value, "mode [1]": mode, "seeds [1]": min(len(g.get(x, {})) for x in SLOPE_RATIOS),
                   "wall_s_mean [s]": f"{sum(walls[value].values()) / len(walls[value]):.1f}"}
            for x in SLOPE_RATIOS:
                m, h = mean_ci95(list(g.get(x, {}).values()))
                row[f"reduction_db_{round(100 * x)}pct_mean [dB]"], row[f"reduction_db_{round(100 * x)}pct_ci95 [dB]"] = f"{m:.2f}", f"{h:.2f}"
            for lo, hi in zip(SLOPE_RATIOS, SLOPE_RATIOS[1:]):
                a, b = g.get(lo, {}), g.get(hi, {})
                m, h = mean_ci95([b[k] - a[k] for k in b if k in a])
                tag = f"{round(100 * hi)}_minus_{round(100 * lo)}"
                row[f"slope_db_{tag}_mean [dB]"], row[f"slope_db_{tag}_ci95 [dB]"] = f"{m:.2f}", f"{h:.2f}"
            table.append(row)
        done(table, per_start)


def rows_of_set(study_toml):
    """A study.toml's `set` list (the overrides of its every run), as --set arguments."""
    import tomllib
    with open(study_toml, "rb") as f:
        return [m.replace(" = ", "=", 1) for m in tomllib.load(f).get("set", [])]


def clearance_rows(groups):
    """clearance.csv's rows: per bag radius and mode, the peak reduction over the starts and d / X at
    the damped peak (reduced.csv's clearance_ratio = d / |X| at the frequency nearest the peak)."""
    table = []
    for (radius, mode), g in sorted(groups.items()):
        db = mean_ci95([x for x, _ in g])
        dx = mean_ci95([float(q["clearance_ratio [1]"]) for _, q in g])
        d = mean_ci95([float(q["clearance_ratio [1]"]) * float(q["cavity_amplitude [m]"]) for _, q in g])
        table.append({"bag_radius_mm": f"{1e3 * radius:g}", "mode [1]": mode, "seeds [1]": len(g),
                      "reduction_db_mean [dB]": f"{db[0]:.4g}", "reduction_db_ci95 [dB]": f"{db[1]:.3g}",
                      "clearance_mean [m]": f"{d[0]:.4g}", "d_over_x_mean [1]": f"{dx[0]:.4g}", "d_over_x_ci95 [1]": f"{dx[1]:.3g}"})
    return table


def slope(points):
    """Least-squares slope of (x, y) points and its 95% half-width (Student t on n - 2 degrees of
    freedom, from the residuals): (slope, half-width)."""
    n = len(points)
    if n < 3:
        return math.nan, math.nan
    mx, my = sum(x for x, _ in points) / n, sum(y for _, y in points) / n
    sxx = sum((x - mx) ** 2 for x, _ in points)
    b = sum((x - mx) * (y - my) for x, y in points) / sxx
    s2 = sum((y - my - b * (x - mx)) ** 2 for x, y in points) / (n - 2)
    t95 = 2.0 + 2.4 / (n - 2) if n - 2 > 3 else {1: 12.706, 2: 4.303, 3: 3.182}[n - 2]  # within 2% of t for n - 2 >= 4
    return b, t95 * math.sqrt(s2 / sxx)


def compare(a, b, unit="dB", digits=".1f"):
    """Is a above b? (mean, half-width) pairs: 'holds' when the difference exceeds the half-widths
    combined in quadrature, 'fails' when it is below minus that, else 'not resolved'."""
    d = a[0] - b[0]
    if not math.isfinite(d):
        return "no data", "no data"
    h = math.hypot(a[1] if math.isfinite(a[1]) else 0, b[1] if math.isfinite(b[1]) else 0)
    return ("holds" if d > h else "fails" if d < -h else "not resolved"), f"{d:+{digits}} +- {h:{digits.lstrip('+')}} {unit}"


def claims(studies, impact_level=None, clearance_level=None):
    """The source study's claims (smaller balls, mass ratio, position, clearance, the bag against a slug),
    each judged per mode on the intervals over the starts. studies: name -> per_seed groups; the
    impact claim also at impact_level (the force of studies "impact-bag" and "impact-slug"), the clearance
    claim also at clearance_level (study "clearance-force", mode 1)."""
    out = []
    def at(name, value, mode, pick=lambda x, q: x):
        g = next((g for (v, m), g in studies.get(name, {}).items() if m == mode and math.isclose(v, value, rel_tol=1e-6)), [])
        return mean_ci95([pick(x, q) for x, q in g])
    for mode in (1, 3):
        small = at("ball-size", 0.004, mode)
        verdicts = [(d, *compare(small, at("ball-size", d, mode))) for d in (0.008, 0.010, 0.020)]
        v = "holds" if all(x[1] == "holds" for x in verdicts) else "fails" if any(x[1] == "fails" for x in verdicts) else "not resolved"
        out.append(("smaller balls damp better: 4 mm above 8, 10 and 20 mm", mode, v,
                    "; ".join(f"4 - {1e3 * d:g} mm: {t} ({x})" for d, x, t in verdicts)))
        runs = [(100 * v, x) for (v, m), g in studies.get("mass-ratio", {}).items() if m == mode for x, _ in g]
        low, high = slope([p for p in runs if p[0] < 9.5]), slope([p for p in runs if p[0] > 9.5])
        v, t = compare(slope(runs), (0.0, 0.0), "dB per %", ".2f")
        out.append(("damping rises with mass ratio: the slope over 5-14% above zero", mode, v, f"slope {t}"))
        v, t = compare(low, high, "dB per %", ".2f")
        out.append(("and levels off: the slope over 5-9% above that over 10-14%", mode, v,
                    f"slopes {low[0]:+.2f} and {high[0]:+.2f} dB per %; difference {t}"))
        nodes = {1: (0.224, 0.776), 3: (0.095, 0.356, 0.644, 0.905)}[mode]
        best_node = max((at("position", x * PIPE_LENGTH, mode) + (x,) for x in nodes), key=lambda m: m[0])
        v, t = compare(at("position", 0.5 * PIPE_LENGTH, mode), best_node[:2])
        out.append((f"position: mid-span (an antinode) above the best node of mode {mode}", mode, v,
                    f"x/L 0.5 - x/L {best_node[2]}: {t}"))
        for name, label in (("clearance", "an optimum clearance exists inside the range run"),
                            ("clearance-force", f"an optimum clearance exists inside the range run, at {clearance_level} "
                                                "(d/X near the rigid impact damper's pi/3 to 3 pi)")):
            radii = sorted({r for r, m in studies.get(name, {}) if m == mode})
            if not radii:
                continue
            means = [at(name, r, mode) for r in radii]
            dx = [at(name, r, mode, lambda x, q: float(q["clearance_ratio [1]"]))[0] for r in radii]
            k = max(range(len(radii)), key=lambda i: means[i][0])
            if 0 < k < len(radii) - 1:
                (v1, t1), (v2, t2) = compare(means[k], means[0]), compare(means[k], means[-1])
                v = "holds" if v1 == v2 == "holds" else "not resolved"
                ev = f"best at bag radius {1e3 * radii[k]:g} mm: {t1} above the smallest, {t2} above the largest"
            else:
                v, ev = "fails", f"largest reduction at the end of the range (bag radius {1e3 * radii[k]:g} mm)"
            out.append((label, mode, v, ev + f"; d/X {min(dx):.3g}-{max(dx):.3g}"))
        bag, slug = at("mass-ratio", 0.08, mode), at("slug", 0.0, mode)
        v, t = compare(bag, slug)
        out.append(("the bag (8% of 4-mm balls) beats a slug of equal mass (cases/pipe-slug)", mode, v, t))
        force = lambda x, q: float(q["peak_impact_force [N]"])
        duration = lambda x, q: float(q["impact_duration [s]"])
        v1, t1 = compare(at("slug", 0.0, mode, force), at("mass-ratio", 0.08, mode, force), "N", ".3g")
        v2, t2 = compare(at("mass-ratio", 0.08, mode, duration), at("slug", 0.0, mode, duration), "s", ".3g")
        # An "impact" lasting 40% of a period or more is contact kept through the cycle (no free flight).
        flight = [float(q["impact_duration [s]"]) * float(q["frequency [Hz]"]) < 0.4
                  for name in ("slug", "mass-ratio") for (val, m), g in studies.get(name, {}).items()
                  if m == mode and (name == "slug" or math.isclose(val, 0.08)) for _, q in g]
        verdict = "holds" if v1 == v2 == "holds" else "fails" if "fails" in (v1, v2) else "not resolved"
        if flight and not all(flight):
            verdict = "not applicable"
        out.append(("with a lower peak force and a longer impact (at the damped peak)", mode, verdict,
                    f"slug - bag peak force {t1} ({v1}); bag - slug duration {t2} ({v2})" +
                    ("" if all(flight) else "; the contacts last 40% of a period or more: the contents do not fly")))
        if impact_level and "impact-bag" in studies and "impact-slug" in studies:  # the same at a force where they fly
            v1, t1 = compare(at("impact-slug", 0.0, mode, force), at("impact-bag", 0.0, mode, force), "N", ".3g")
            v2, t2 = compare(at("impact-bag", 0.0, mode, duration), at("impact-slug", 0.0, mode, duration), "s", ".3g")
            fly = [float(q["impact_duration [s]"]) * float(q["frequency [Hz]"]) for name in ("impact-bag", "impact-slug")
                   for (_, m), g in studies[name].items() if m == mode for _, q in g]
            verdict = "holds" if v1 == v2 == "holds" else "fails" if "fails" in (v1, v2) else "not resolved"
            if not fly or max(fly) >= 0.4:
                verdict = "not applicable"
            out.append((f"with a lower peak force and a longer impact, at {impact_level} (the base case's bag against "
                        "cases/pipe-slug)", mode, verdict,
                        f"slug - bag peak force {t1} ({v1}); bag - slug duration {t2} ({v2}); impacts last "
                        f"{min(fly, default=math.nan):.2f}-{max(fly, default=math.nan):.2f} of a period"))
    return [{"claim": c, "mode [1]": m, "verdict": v, "evidence": e} for c, m, v, e in out]


def write_csv(path, columns, table):
    with open(path + ".part", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        w.writerows(table)
    os.replace(path + ".part", path)
    print(path)


def plot(table, docs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    written = []
    for name, _, param, _ in STUDIES:
        sel = [r for r in table if r["study"] == name]
        fig, ax = plt.subplots(figsize=(7.5, 4.8))
        for mode, marker in ((1, "o"), (3, "s")):
            pts = sorted((float(r["value"]), float(r["reduction_db_mean [dB]"]), float(r["reduction_db_ci95 [dB]"] or "nan"))
                         for r in sel if float(r["mode [1]"]) == mode)
            if not pts:
                continue
            x, y, e = zip(*pts)
            ax.errorbar(x, y, yerr=[0 if math.isnan(v) else v for v in e], fmt=marker + "-", capsize=3, label=f"mode {mode} (DEM, 95% interval over the seeds)")
        for mode, db in TABLE3:
            ax.axhline(db, ls=":", lw=0.8, color="0.4")
        ax.set_xlabel({"ball_diameter_mm": "ball diameter [mm]", "mass_ratio_pct": "mass ratio [%]", "position_xL": "bag position x/L"}[param])
        ax.set_ylabel("peak reduction [dB]")
        ax.set_title(f"{name} study at the calibrated level (dotted: the study's Table 3, 14.9 / 14.5 dB)", fontsize=10)
        ax.grid(True, alpha=0.4)
        ax.legend(fontsize=9)
        fig.tight_layout()
        path = os.path.join(docs, f"study_{name}.png")
        fig.savefig(path, dpi=150)
        plt.close(fig)
        written.append(path)
    return written


def main(argv):
    import argparse
    p = argparse.ArgumentParser(prog="tools/validate-study", description="The source study's studies at the calibrated force, modes 1 and 3.")
    p.add_argument("--amplitude", default="0.04 N", help='the force amplitude (default "0.04 N")')
    p.add_argument("--damping-ratio", help="the pipe's damping ratio (default: calibrated on Table 3 first)")
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--out", default=os.path.join(ROOT, "validation-study"), help="where the runs go (default ./validation-study)")
    p.add_argument("--docs", default=os.path.join(ROOT, "docs", "validation"), help="where study.csv and the figures go")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--keys", action="store_true", help="also vary each candidate key alone (step 4) and write keys.csv")
    p.add_argument("--table3", action="store_true",
                   help="only step 6: the pipe's damping ratio fitted to all 20 figures of Table 3 at --amplitude, calibrate-table3.csv")
    p.add_argument("--table3-maps", action="store_true",
                   help="only step 7: a map per Table 3 mass ratio, then the force and damping ratios fitted on them to all 20 figures")
    p.add_argument("--table3-check", action="store_true",
                   help="only step 8: Table 3 by coupled DEM at --amplitude and --damping-ratio (mode 3 at --damping-ratio3), "
                        "table3-check.csv and table3-check-summary.csv (the MAE per mode)")
    p.add_argument("--damping-ratio3", help="with --table3-check: mode 3's damping ratio (default --damping-ratio)")
    p.add_argument("--table3-modes", default="1,3", help="with --table3-check: the modes run (comma-separated, default 1,3)")
    p.add_argument("--slope", action="store_true",
                   help="only step 5: the mass-ratio trend's slope (5, 8, 12%%) with each model choice varied, slope.csv (needs --damping-ratio)")
    p.add_argument("--slope-choices", help="with --slope: only these (comma-separated: base, tightness, force, ball-stiffness, "
                   "bag-radius, film-thickness, bag-length; empty: none run); slope.csv holds every choice whose runs are in --out")
    p.add_argument("--clearance-amplitude", default="0.5 N",
                   help='the force at which the clearance study is also run, mode 1, bag radius 7-11 mm (default "0.5 N")')
    p.add_argument("--impact-amplitude", default="0.2 N",
                   help='the force at which the bag and the slug are also compared for the impact claim (default "0.2 N")')
    a = p.parse_args(argv)
    if not os.access(BAGDEM, os.X_OK):
        sys.exit(f"tools/validate-study: no {BAGDEM}: run tools/validate-study (it builds), not this file")
    os.makedirs(a.docs, exist_ok=True)
    zeta = a.damping_ratio
    if a.table3:
        calibrate_table3(a.out, a.amplitude, a.seeds, a.jobs, a.docs)
        return 0
    if a.table3_check:
        if zeta is None:
            sys.exit("tools/validate-study: --table3-check needs --damping-ratio (and --amplitude)")
        modes = sorted({int(m) for m in a.table3_modes.split(",")})
        if not set(modes) <= {1, 3}:
            sys.exit(f"tools/validate-study: --table3-modes {a.table3_modes}: Table 3 has modes 1 and 3")
        zetas = {1: zeta, 3: a.damping_ratio3 or zeta}
        table3_check(a.out, a.amplitude, {m: zetas[m] for m in modes}, a.seeds, a.jobs, a.docs)
        return 0
    if a.table3_maps:
        calibrate_table3_maps(a.out, a.seeds, a.jobs, a.docs)
        return 0
    if a.slope:
        if zeta is None:
            sys.exit("tools/validate-study: --slope needs --damping-ratio (the calibrated one: docs/validation/README.md)")
        level = [f'excitation.amplitude="{a.amplitude}"', f"primary.damping_ratio={zeta}"]
        columns = ["key", "value", "mode [1]", "seeds [1]"]
        for x in SLOPE_RATIOS:
            columns += [f"reduction_db_{round(100 * x)}pct_mean [dB]", f"reduction_db_{round(100 * x)}pct_ci95 [dB]"]
        for lo, hi in zip(SLOPE_RATIOS, SLOPE_RATIOS[1:]):
            columns += [f"slope_db_{round(100 * hi)}_minus_{round(100 * lo)}_mean [dB]", f"slope_db_{round(100 * hi)}_minus_{round(100 * lo)}_ci95 [dB]"]
        chosen = None if a.slope_choices is None else set(filter(None, a.slope_choices.split(",")))
        names = {"base"} | {name for _, name, _ in SLOPE_CHOICES}
        if chosen is not None and not chosen <= names:
            sys.exit(f"tools/validate-study: --slope-choices {a.slope_choices}: allowed are {', '.join(sorted(names))}")

        def done(table, per_start):  # written after each choice, so that a stopped study keeps what it measured
            write_csv(os.path.join(a.docs, "slope.csv"), columns + ["wall_s_mean [s]"], table)
            write_csv(os.path.join(a.docs, "slope-seeds.csv"), ["key", "value", "mode [1]", "mass_ratio [1]", "seed",
                                                                 "reduction_dB [dB]", "wall_s [s]"], per_start)
        slope_rows(a.out, level, a.seeds, a.jobs, chosen, done)
        return 0
    if zeta is None:
        cal, zeta = calibrate(a.out, a.amplitude, a.seeds, a.jobs)
        for name in ("calibration.json", "calibrate.csv"):
            stem, ext = os.path.splitext(name)
            shutil.copy(os.path.join(cal, name), os.path.join(a.docs, f"{stem}-modes13{ext}"))
        if subprocess.call([os.path.join(ROOT, "tools", "plot"), cal, "--out", cal]) == 0:
            shutil.copy(os.path.join(cal, "calibrate.png"), os.path.join(a.docs, "calibrate-modes13.png"))
    level = [f'excitation.amplitude="{a.amplitude}"', f"primary.damping_ratio={zeta}"]
    print(f"level: {', '.join(level)}", flush=True)
    table, continuum, groups = [], [], {}
    for name, study, param, convert in STUDIES:
        out = os.path.join(a.out, name)
        args = [BAGDEM, "sweep", os.path.join(ROOT, study), "--seeds", str(a.seeds), "--out", out, "--jobs", str(a.jobs)]
        for m in level + MODES:
            args += ["--set", m]
        run(args)
        table += study_rows(name, out, param, convert)
        continuum += continuum_rows(name, out, param, convert)
        groups[name] = per_seed(out)
    write_csv(os.path.join(a.docs, "study.csv"), ["study", "param", "value", "mode [1]", "reduction_db_mean [dB]",
                                                   "reduction_db_ci95 [dB]", "seeds [1]", "mass_ratio_actual [1]"], table)
    columns = ["study", "param", "value", "mode [1]", "seeds [1]", "dem_reduction_db_mean [dB]"]
    for model, _ in CONTINUUM:
        columns += [f"{model}_minus_dem_db_mean [dB]", f"{model}_minus_dem_db_ci95 [dB]", f"{model}_median_abs_error [1]"]
    write_csv(os.path.join(a.docs, "continuum.csv"), columns, continuum)
    write_csv(os.path.join(a.docs, "continuum-summary.csv"), ["study", "mode [1]", "model", "points [1]", "mean_minus_dem_db [dB]",
                                                               "max_abs_minus_dem_db [dB]", "median_abs_error [1]"],
              continuum_summary(continuum))
    out = os.path.join(a.out, "clearance")
    args = [BAGDEM, "sweep", os.path.join(ROOT, "cases/studies/clearance"), "--seeds", str(a.seeds), "--out", out, "--jobs", str(a.jobs)]
    for m in level + MODES:
        args += ["--set", m]
    run(args)
    write_csv(os.path.join(a.docs, "clearance.csv"), ["bag_radius_mm", "mode [1]", "seeds [1]", "reduction_db_mean [dB]",
                                                       "reduction_db_ci95 [dB]", "clearance_mean [m]", "d_over_x_mean [1]",
                                                       "d_over_x_ci95 [1]"], clearance_rows(groups.setdefault("clearance", per_seed(out))))
    # At the calibrated level d/X is far above a rigid impact damper's optimum (the bag cannot be made
    # to fit the bore closer than its film's folds): the same bag radii, mode 1, at a force where the
    # contents fly and d/X comes down to pi/3 - 3 pi.
    out = os.path.join(a.out, "clearance-force")
    args = [BAGDEM, "sweep", os.path.join(ROOT, "cases/studies/clearance"), "--seeds", str(a.seeds), "--out", out, "--jobs", str(a.jobs),
            "--vary", "bag.radius=" + ",".join(f'"{r} mm"' for r in CLEARANCE_FORCE_RADII)]
    for m in [f'excitation.amplitude="{a.clearance_amplitude}"', f"primary.damping_ratio={zeta}", "excitation.around_modes=[1]", MODES[1]]:
        args += ["--set", m]
    run(args)
    groups["clearance-force"] = per_seed(out)
    write_csv(os.path.join(a.docs, "clearance-force.csv"), ["bag_radius_mm", "mode [1]", "seeds [1]", "reduction_db_mean [dB]",
                                                             "reduction_db_ci95 [dB]", "clearance_mean [m]", "d_over_x_mean [1]",
                                                             "d_over_x_ci95 [1]"], clearance_rows(groups["clearance-force"]))
    out = os.path.join(a.out, "slug")
    args = [BAGDEM, "run", os.path.join(ROOT, "cases/pipe-slug"), "--seeds", str(a.seeds), "--out", out]
    for m in level + MODES:
        args += ["--set", m]
    run(args)
    groups["slug"] = per_seed(out)
    # The impact claim needs contents that fly: the base case's bag and the slug again at a higher force.
    impact = [f'excitation.amplitude="{a.impact_amplitude}"', f"primary.damping_ratio={zeta}"] + MODES
    for name, case in (("impact-bag", "cases/pipe-beanbag"), ("impact-slug", "cases/pipe-slug")):
        out = os.path.join(a.out, name)
        args = [BAGDEM, "run", os.path.join(ROOT, case), "--seeds", str(a.seeds), "--out", out]
        for m in impact:
            args += ["--set", m]
        run(args)
        groups[name] = per_seed(out)
    verdicts = claims(groups, a.impact_amplitude, a.clearance_amplitude)
    write_csv(os.path.join(a.docs, "claims.csv"), ["claim", "mode [1]", "verdict", "evidence"], verdicts)
    for c in verdicts:
        print(f"  mode {c['mode [1]']}: {c['claim']}: {c['verdict']} ({c['evidence']})")
    for p in plot(table, a.docs):
        print(p)
    if a.keys:
        write_csv(os.path.join(a.docs, "keys.csv"), ["key", "value", "mode [1]", "reduction_db_mean [dB]", "reduction_db_ci95 [dB]",
                                                      "paired_change_db_mean [dB]", "paired_change_db_ci95 [dB]", "seeds [1]"],
                  keys(a.out, level, zeta, a.seeds, a.jobs))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
