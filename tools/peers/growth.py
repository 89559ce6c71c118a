#!/usr/bin/python3
"""Helper of tools/peers/growth.

  growth.py tile PEERS OUT k...   writes the peers' settled N = 1000 bed (runs/N1000.vib1.data)
                                  tiled k x k as OUT/data.k<k>, with the widened box for
                                  LIGGGHTS (OUT/inputs/box.Nk<k>.stl) and LAMMPS
                                  (OUT/inputs/geom.Nk<k>.in)
  growth.py report RESULTS        the table and the fitted exponents from lines "code N ns"

The tiling is bagdem bench --growth's (src/run/bench.cpp, run_growth_bench): copy (i, j) of the bed
shifted by (i L, j L, 0), L = 63 mm the box's inner side, and the box widened to k L x k L x 48 mm.
"""
import os
import re
import statistics as st
import sys

import numpy as np

L, H = 0.063, 0.048  # the N = 1000 box's inner side and height (peers/inputs/geom.N1000.in)


def tile(peers, out, ks):
    os.makedirs(f"{out}/inputs", exist_ok=True)
    lines = open(f"{peers}/runs/N1000.vib1.data").read().split("\n")
    a, v = lines.index("Atoms"), lines.index("Velocities")
    atoms = [l.split() for l in lines[a + 1:v] if l.strip()]
    vels = [l.split() for l in lines[v + 1:] if l.strip()]
    assert len(atoms) == len(vels) == 1000, "expected the 1000-ball bed"
    stl = open(f"{peers}/inputs/box.N1000.stl").read()
    for k in ks:
        rows, vrows = [], []
        for i in range(k):
            for j in range(k):
                for at, ve in zip(atoms, vels):
                    n = len(rows) + 1
                    x, y = float(at[4]) + i * L, float(at[5]) + j * L
                    rows.append(f"{n} {at[1]} {at[2]} {at[3]} {x:.17e} {y:.17e} {at[6]} 0 0 0")
                    vrows.append(f"{n} " + " ".join(ve[1:]))
        with open(f"{out}/data.k{k}", "w") as f:
            f.write(f"PD-box bed of 1000 balls tiled {k} x {k}\n\n{len(rows)} atoms\n1 atom types\n\n")
            for axis in ("x", "y"):
                f.write(f"-0.003 {k * L + 0.003!r} {axis}lo {axis}hi\n")
            f.write("-0.003 0.051 zlo zhi\n\nAtoms\n\n" + "\n".join(rows) + "\n\nVelocities\n\n" + "\n".join(vrows) + "\n")
        widened = re.sub(r"vertex (\S+) (\S+) (\S+)",
                         lambda m: f"vertex {float(m[1]) * k!r} {float(m[2]) * k!r} {m[3]}", stl)
        open(f"{out}/inputs/box.Nk{k}.stl", "w").write(widened)
        open(f"{out}/inputs/geom.Nk{k}.in", "w").write(f"variable Lbox equal {k * L!r}\nvariable Hbox equal {H}\n")


def report(path):
    runs = {}
    for line in open(path):
        code, n, ns = line.split()
        runs.setdefault(code, {}).setdefault(int(n), []).append(float(ns))
    codes = [c for c in ("bagdem", "liggghts", "lammps") if c in runs]
    sizes = sorted(runs["bagdem"])
    print("PD-box bed tiled k x k, one core, ns per particle-step (median of the rounds, min-max)")
    print("| N | " + " | ".join(codes) + " | LIGGGHTS / bagdem |")
    print("|---|" + "---|" * (len(codes) + 1))
    med = {c: [st.median(runs[c][n]) for n in sizes] for c in codes}
    for i, n in enumerate(sizes):
        cells = [f"{med[c][i]:.1f} ({min(runs[c][n]):.1f}-{max(runs[c][n]):.1f})" for c in codes]
        ratio = f"{med['liggghts'][i] / med['bagdem'][i]:.2f}" if "liggghts" in med else "-"
        print(f"| {n} | " + " | ".join(cells) + f" | {ratio} |")
    if len(sizes) < 2:
        return  # no exponent from one size
    print("\nFitted exponent a of wall time per step ~ N^a (least squares over the sizes; flat cost is a = 1):")
    def fit(y):
        return 1 + np.polyfit(np.log(sizes), np.log(y), 1)[0]

    for c in codes:
        rounds = min(len(runs[c][n]) for n in sizes)
        each = " / ".join(f"{fit([runs[c][n][r] for n in sizes]):.3f}" for r in range(rounds))
        print(f"  {c}: a = {fit(med[c]):.3f} (medians); round by round {each}")


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "tile":
        tile(sys.argv[2], sys.argv[3], [int(k) for k in sys.argv[4:]])
    elif len(sys.argv) == 3 and sys.argv[1] == "report":
        report(sys.argv[2])
    else:
        sys.exit(__doc__)
