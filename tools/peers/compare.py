#!/usr/bin/python3
"""Helper of tools/peers/compare.

  compare.py jitter SRC DST SEED [DV]   writes the LAMMPS data file SRC as DST with every ball's
                                        velocity changed by DV m/s (default 1e-6) in a random
                                        direction drawn by numpy's default_rng(SEED); positions,
                                        angular velocities and everything else are copied as is
  compare.py table LIG_JSON CSV N       one start: each code's M_eff and C_eff with its
                                        cycle-to-cycle standard error, and their differences
  compare.py record DIR                 one start of an ensemble: DIR/lig.json (analyze_force.py),
                                        DIR/bagdem/reduced.csv and the codes' run times
                                        (DIR/lig.seconds, DIR/bagdem.seconds) into DIR/result.json
  compare.py ensemble N DIR...          the ensemble of the starts' result.json: each code's mean
                                        with a 95% interval, the difference of the codes and its
                                        interval, the run time

The interval of a mean over n starts is Student's t: mean +- t(0.975, n - 1) sd / sqrt(n), with sd
the sample standard deviation (n - 1) of the starts' figures. The difference is paired (the codes
run from the same jittered bed): the same interval of the starts' differences bagdem - LIGGGHTS.
"""
import csv
import json
import math
import os
import sys

import numpy as np

OMEGA = 2 * math.pi * 30.0  # the box's angular frequency (30 Hz)


def jitter(src, dst, seed, dv=1e-6):
    lines = open(src).read().split("\n")
    v = lines.index("Velocities")
    rows = [i for i in range(v + 1, len(lines)) if lines[i].strip()]
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(len(rows), 3))
    u *= dv / np.linalg.norm(u, axis=1)[:, None]
    for i, du in zip(rows, u):
        f = lines[i].split()
        vel = [float(x) + d for x, d in zip(f[1:4], du)]
        lines[i] = " ".join([f[0]] + [f"{x:.17e}" for x in vel] + f[4:])
    tmp = dst + ".tmp"
    open(tmp, "w").write("\n".join(lines))
    os.replace(tmp, dst)


def reduced(path):
    row = next(csv.DictReader(open(path)))
    return lambda name: next(float(v) for k, v in row.items() if k.split(" [")[0] == name)


def table(lig_json, csv_path, n_balls):
    lig = json.load(open(lig_json))
    col = reduced(csv_path)
    n = lig["cycles"]
    se = lambda sd: sd / math.sqrt(n) if sd is not None else float("nan")
    m_l, c_l = lig["M_eff"], lig["C_eff"]
    m_b, c_b = col("M_eff"), col("C_eff")
    print(f"PD-box, N = {n_balls}: x-force of the balls on the box, first harmonic over {n} whole periods after {lig['skip_cycles']:g}")
    print("| quantity | LIGGGHTS 3.8 | bagdem | bagdem - LIGGGHTS |")
    print("|---|---|---|---|")
    print(f"| M_eff (kg) | {m_l:.5g} +- {se(lig['M_eff_percycle_std']):.2g} | {m_b:.5g} +- {col('M_eff_se'):.2g} | {100 * (m_b / m_l - 1):+.1f}% |")
    print(f"| C_eff (N s/m) | {c_l:.5g} +- {se(lig['C_eff_percycle_std']):.2g} | {c_b:.5g} +- {col('C_eff_se'):.2g} | {100 * (c_b / c_l - 1):+.1f}% |")
    print(f"| M_eff / bed mass | {m_l / lig['total_mass']:.4f} | {m_b / lig['total_mass']:.4f} | |")
    print(f"| C_eff / (bed mass w) | {c_l / (lig['total_mass'] * OMEGA):.4f} | {c_b / (lig['total_mass'] * OMEGA):.4f} | |")


def record(d):
    lig = json.load(open(f"{d}/lig.json"))
    col = reduced(f"{d}/bagdem/reduced.csv")
    seconds = lambda code: float(open(f"{d}/{code}.seconds").read())
    res = dict(cycles=lig["cycles"], skip_cycles=lig["skip_cycles"], total_mass=lig["total_mass"],
               liggghts=dict(M_eff=lig["M_eff"], C_eff=lig["C_eff"], seconds=seconds("lig")),
               bagdem=dict(M_eff=col("M_eff"), C_eff=col("C_eff"), seconds=seconds("bagdem")))
    tmp = f"{d}/result.json.{os.getpid()}"
    json.dump(res, open(tmp, "w"), indent=1)
    os.replace(tmp, f"{d}/result.json")


def t975(dof):
    """t(0.975, dof), as bagdem's reduce/interval.cpp computes it: tables up to 10 degrees of freedom
    (Abramowitz & Stegun 26.10), the Cornish-Fisher expansion above (A&S 26.7.5), within 1e-4."""
    table = (12.7062, 4.3027, 3.1824, 2.7764, 2.5706, 2.4469, 2.3646, 2.3060, 2.2622, 2.2281)
    if dof < 1:
        return math.nan
    if dof <= len(table):
        return table[dof - 1]
    z, n = 1.959963984540054, float(dof)
    return (z + (z**3 + z) / (4 * n) + (5 * z**5 + 16 * z**3 + 3 * z) / (96 * n**2)
            + (3 * z**7 + 19 * z**5 + 17 * z**3 - 15 * z) / (384 * n**3)
            + (79 * z**9 + 776 * z**7 + 1482 * z**5 - 1920 * z**3 - 945 * z) / (92160 * n**4))


def interval(xs):
    """Mean and the half-width of its 95% interval (Student t over the values, n - 1 degrees)."""
    x = np.asarray(xs, dtype=float)
    n = len(x)
    return float(x.mean()), float(t975(n - 1) * x.std(ddof=1) / math.sqrt(n))


def ensemble(n_balls, dirs):
    res = [json.load(open(f"{d}/result.json")) for d in dirs]
    n = len(res)
    if n < 2:
        sys.exit("compare.py ensemble: an interval needs at least 2 starts")
    print(f"PD-box, N = {n_balls}: {n} starts (the settled bed, velocities jittered by 1e-6 m/s), "
          f"first harmonic over {res[0]['cycles']} periods after {res[0]['skip_cycles']:g}; "
          f"mean +- half-width of the 95% interval (t({0.975}, {n - 1}) = {t975(n - 1):.3f})")
    print("| quantity | LIGGGHTS 3.8 | bagdem | bagdem - LIGGGHTS (paired) |")
    print("|---|---|---|---|")
    for q, unit, fmt in (("M_eff", "kg", ".4g"), ("C_eff", "N s/m", ".4g")):
        lig = [r["liggghts"][q] for r in res]
        bag = [r["bagdem"][q] for r in res]
        (ml, hl), (mb, hb) = interval(lig), interval(bag)
        md, hd = interval([b - l for b, l in zip(bag, lig)])
        print(f"| {q} ({unit}) | {ml:{fmt}} +- {hl:{fmt}} | {mb:{fmt}} +- {hb:{fmt}} | "
              f"{md:+{fmt}} +- {hd:{fmt}} ({100 * md / ml:+.1f}% +- {100 * hd / abs(ml):.1f}% of LIGGGHTS) |")
    print("\nEach start:")
    print("| start | LIGGGHTS M_eff (kg) | LIGGGHTS C_eff (N s/m) | bagdem M_eff (kg) | bagdem C_eff (N s/m) | LIGGGHTS (s) | bagdem (s) |")
    print("|---|---|---|---|---|---|---|")
    for d, r in zip(dirs, res):
        l, b = r["liggghts"], r["bagdem"]
        print(f"| {os.path.basename(os.path.normpath(d))} | {l['M_eff']:.4g} | {l['C_eff']:.4g} | {b['M_eff']:.4g} | "
              f"{b['C_eff']:.4g} | {l['seconds']:.0f} | {b['seconds']:.0f} |")
    tl = sum(r["liggghts"]["seconds"] for r in res)
    tb = sum(r["bagdem"]["seconds"] for r in res)
    print(f"\nRun time (wall clock, one core each): LIGGGHTS {tl / 60:.1f} min, bagdem {tb / 60:.1f} min "
          f"over the {n} starts ({tl / n:.0f} s and {tb / n:.0f} s a start)")


if __name__ == "__main__":
    a = sys.argv[1:]
    if len(a) in (4, 5) and a[0] == "jitter":
        jitter(a[1], a[2], int(a[3]), float(a[4]) if len(a) == 5 else 1e-6)
    elif len(a) == 4 and a[0] == "table":
        table(a[1], a[2], a[3])
    elif len(a) == 2 and a[0] == "record":
        record(a[1])
    elif len(a) >= 2 and a[0] == "ensemble":
        ensemble(a[1], a[2:])
    else:
        sys.exit(__doc__)
