// Damping coefficient of the Hertz contact from a requested restitution e.
//
// Damping force (Tsuji, Tanaka & Ishida 1992, as in LIGGGHTS/EDEM):
//     F_d = gamma_n * d(delta)/dt,  gamma_n = 2 sqrt(5/6) |beta| sqrt(S_n m*),  S_n = 2 E* sqrt(R* delta).
// With F_el = k delta^(3/2) (k = 4/3 E* sqrt(R*)) the impact in units delta0 = (m* v^2/k)^(2/5),
// t0 = delta0/v obeys x'' = -x^(3/2) - a x^(1/4) x' with a = sqrt(5)|beta|: the restitution depends
// on a only, never on the impact speed.
//
//  * tsuji_beta(e) = ln(e)/sqrt(ln(e)^2 + pi^2) is the classic choice. It returns e only if the
//    total normal force may turn tensile at the end of the impact.
//  * clamped_beta(e) is the |beta| for which the same law, with the total normal force clamped at
//    zero (dry balls cannot pull), returns e. It is computed, not fitted: the dimensionless ODE above
//    is integrated with RK4 (event located at the clamp or at x = 0) and inverted by bisection, so it
//    is exact to the integration tolerance (<1e-6 in e) for any e in (0, 1]. This is bagdem's
//    calibration; it serves the same purpose as the fit of Thornton, Cummins & Cleary (2013).
#pragma once

namespace bagdem {

// Classic Tsuji beta (negative), docs/reference-study.md, section 4.
double tsuji_beta(double e);

// Restitution of the dimensionless Hertz impact with damping parameter a = sqrt(5)|beta|.
// clamped = true: total normal force max(0, .). Returns e in [0, 1].
double restitution_of_damping(double a, bool clamped);

// |beta| such that the clamped law returns e (e in (0, 1]; e = 1 gives 0).
double clamped_beta(double e);

}  // namespace bagdem
