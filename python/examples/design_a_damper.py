#!/usr/bin/env python3
"""From one's own structure to a design, in Python (docs/python.md walks through it).

The structure: a 20-g mass on a spring (20 Hz, 2% damping), driven by a 2-mN stepped sine, with a
40 x 20 x 20 mm steel cavity on it. Its answer is known, which is why it is the example: a ball
rolling without slip on the cavity's floor adds 2/7 of its mass and no damping, so every candidate
lowers the peak by 20 log10(zeta' sqrt(1 - zeta'^2) / (zeta sqrt(1 - zeta^2))) dB with
zeta' = zeta sqrt(M / (M + 2m/7)) (tests/test_design.cpp). Swap in your own structure ([primary],
docs/case-schema.md) and bag (cases/pipe-beanbag) and the steps are the same.

    PYTHONPATH=python python3 python/examples/design_a_damper.py WORK_DIR

Runs in about half a minute on 2 cores; prints each step's figures and writes WORK_DIR/design/*.png.
"""
import math
import os
import sys

import bagdem

STRUCTURE = """\
[simulation]
duration = "0.1 s"
settle = "0.05 s"
gravity = [0, 0, "-9.81 m/s^2"]

[materials.steel]
density = "7800 kg/m^3"
youngs_modulus = "2 GPa"
poisson_ratio = 0.3

[interactions.default]
restitution = 0.5
friction = 0.3

[cavity]                    # the cavity, carried by the structure
kind = "box"
material = "steel"
min = ["-20 mm", "-10 mm", "-10 mm"]
max = ["20 mm", "10 mm", "10 mm"]

[particles.ball]            # what goes in it: the design varies its diameter
material = "steel"
diameter = "10 mm"
positions = [[0, 0, "-4.99 mm"]]  # on the floor; a smaller ball settles onto it

[primary]                   # one's own structure: here a mass on a spring
kind = "sdof"
mass = "20 g"
stiffness = "315.827 N/m"   # 20 Hz
damping_ratio = 0.02
direction = [1, 0, 0]
axis = [0, 1, 0]

[excitation]                # the load it sees: a stepped sine over its resonance
kind = "stepped-sine"
amplitude = "2 mN"
frequencies = [18, 20, 22]
"""

DIAMETERS = ["6 mm", "8 mm", "10 mm"]


def analytic_db(diameter_m, mass=0.02, zeta=0.02, density=7800.0):
    """The rolling ball's peak reduction [dB]: its 2/7 mass added, the damping c fixed."""
    m = density * math.pi * diameter_m ** 3 / 6
    z = zeta * math.sqrt(mass / (mass + 2 * m / 7))
    return 20 * math.log10(z * math.sqrt(1 - z * z) / (zeta * math.sqrt(1 - zeta * zeta)))


def main(work):
    # 1. The case: written once, checked by bagdem (SI units, defaults filled, what is modelled).
    case = bagdem.Case.write(os.path.join(work, "structure"), STRUCTURE)
    print(case.check())

    # 2. One coupled run: the structure's peak with the ball against the bare one, and the
    #    ball's reduced parameters (M_eff/M_bag, C_b/(M_b w)) per frequency.
    coupled = case.run(os.path.join(work, "coupled"), progress=False)
    peaks = coupled.peaks
    print("coupled run:", peaks[["mode [1]", "bare_frequency [Hz]", "frequency [Hz]", "reduction_dB [dB]"]].to_string(index=False))
    reduced = coupled.reduced
    print(reduced[["frequency [Hz]", "gamma [1]", "M_eff_ratio [1]", "Cb_over_Mbw [1]", "e [1]"]].to_string(index=False))

    # 3. The design: each ball characterized once (its effective-field map), predicted on the
    #    structure, ranked under a budget of 15% added mass, the best run coupled with 2 starts.
    design = case.design(os.path.join(work, "design"), vary={"particles.ball.diameter": DIAMETERS}, budget=0.15,
                         gamma=(0.02, 0.5), amplitudes=3, frequencies=2, seeds=2, cycles=6, skip=2, window_time=0,
                         skip_time=0, verify=1, verify_seeds=2, jobs=2, progress=False)
    table = design.design
    print(table[["rank [1]", "status", "particles.ball.diameter", "added_mass [kg]", "objective_dB [dB]", "dem_objective_dB [dB]"]]
          .to_string(index=False))
    ranked = table[table["status"] == "ranked"]
    for diameter, predicted in zip(ranked["particles.ball.diameter"], ranked["objective_dB [dB]"]):
        print(f"{diameter}: predicted {predicted:.4f} dB, analytic {analytic_db(float(diameter.split()[0]) * 1e-3):.4f} dB")
    for figure in design.plot():
        print("figure:", figure)

    # 4. The chosen bag, a case ready to run or to hand on.
    chosen = bagdem.Case(design.file("chosen"))
    print("chosen:", chosen.path)
    return case, coupled, design, chosen


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
