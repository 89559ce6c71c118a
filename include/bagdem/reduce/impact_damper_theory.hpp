// The classic single-ball impact damper: the symmetric two-impacts-per-cycle motion of one ball in a
// cavity under prescribed harmonic motion, its energy dissipation and its stability. A reference for
// the DEM (tests/test_single_ball_damper.cpp) and for the study's continuum model (docs/reference-study.md,
// section 2).
//
// Sources: S. F. Masri & T. K. Caughey, "On the stability of the impact damper", J. Appl. Mech. 33
// (1966) 586-592; S. F. Masri, "General motion of impact dampers", J. Acoust. Soc. Am. 47 (1970)
// 229-237. The derivation below is redone for a cavity with prescribed motion (no primary
// structure), in this code's symbols.
//
// Set-up and conventions (SI). The cavity moves as x(t) = X sin(w t) along one axis. A ball of mass m
// moves freely (no gravity along the axis) between two walls; d is the free travel of its centre
// (cavity inner length minus the ball's diameter); its position relative to the cavity's centre is
// z in [-d/2, d/2]. Impacts are rigid and instantaneous with restitution e in (0, 1):
// (relative speed after) = -e (relative speed before). r = (1 + e)/(1 - e); D = d/X.
//
// 1. The periodic motion. The ball alternates between +u and -u; it meets the left wall (z = -d/2)
//    at phase w t = alpha while the cavity moves at x' = X w cos(alpha) > 0, and the right wall at
//    alpha + pi (x' = -X w cos alpha), by the symmetry x -> -x, t -> t + pi/w of the drive.
//    - Impact: u - X w cos(alpha) = -e (-u - X w cos(alpha))  =>  u = r X w cos(alpha).     (1)
//    - Flight of half a period at speed u from z = -d/2 to z = +d/2:
//      (-X sin alpha + d/2) - (X sin alpha - d/2) = u pi/w  =>  D = pi r cos(alpha) + 2 sin(alpha).  (2)
//    - (2) is R cos(alpha - psi) = D with R = sqrt(pi^2 r^2 + 4), psi = atan2(2, pi r) in (0, pi/2),
//      so a solution exists iff D <= R, and alpha = psi -/+ acos(D/R). u > 0 needs cos(alpha) > 0:
//      the root psi - acos(D/R) always qualifies, psi + acos(D/R) only for D > 2. Section 4 shows
//      the second root is always unstable (a saddle), so the first is the physical one.
//    - Admissibility: between impacts the ball must not touch a wall. With
//      f(theta) = (z + d/2)/X = U (theta - alpha) - sin(theta) + sin(alpha), U = r cos(alpha), one
//      needs 0 < f < D on (alpha, alpha + pi); f is monotone when U >= 1, else its extremes are at
//      cos(theta) = U. It fails below a threshold of D (the wall the ball left catches it again:
//      D < 0.50 at e = 0.6, < 1.21 at e = 0.2), which lies below the stable range of section 4
//      unless e < 0.087 (then it cuts the lower part of that range: from 1.69 to 2.08 at e = 0.05).
// 2. Correspondence with the study (x = X cos(theta), docs/reference-study.md, section 2): theta = w t - pi/2,
//    so the left-wall impact is at theta = alpha - pi/2 and the right-wall one at alpha + pi/2. The
//    study's phi is taken as the latter, phi = alpha + pi/2 in (0, pi), where the cavity speed is
//    w X sin(phi) = w X cos(alpha) > 0 in magnitude (Eq. 11a). Then sin(phi) = cos(alpha),
//    cos(phi) = -sin(alpha), and (2) reads D = pi r sin(phi) - 2 cos(phi): the study's Eq. (22),
//    whose absolute value also covers the other impact (phi - pi).
// 3. Energy. The ball's speed is u before and after each impact, so the energy lost in an impact is
//    the work of the wall's impulse 2 m u at the wall's speed:
//      E_impact = 2 m u X w cos(alpha) = 2 m r (X w cos alpha)^2
//               = (1/2) m (1 - e^2) v_rel^2,  v_rel = u + X w cos(alpha) = 2 X w cos(alpha)/(1 - e),
//    the relative approach speed (the two forms agree identically). E_cycle = 2 E_impact.
//    Equivalent viscous damping (energy per cycle of a dashpot at amplitude X is pi C w X^2):
//      C_eq = E_cycle / (pi w X^2) = (4/pi) m w r cos^2(alpha),
//    i.e. C_eq/(m w) = (4/pi) r sin^2(phi): the study's Eq. (19a) with M_b = m. The impulse train's
//    in-phase fundamental (docs/reference-study.md, section 5: M_eff = (2/(T w^2 X)) int F sin(w t) dt over a
//    cycle, F = force on the cavity: -2 m u at alpha, +2 m u at alpha + pi) gives
//      M_eff = -(4/pi) m r sin(alpha) cos(alpha) = (4/pi) m r sin(phi) cos(phi),
//    the right-hand side of the study's Eq. (19b) with m for M_b (the study writes M_b/M_p there).
// 4. Stability (in the manner of Masri & Caughey 1966). Impact-to-impact map, folded by the drive's
//    symmetry so the periodic motion is a fixed point: state (theta_n, V_n) = (phase of an impact on
//    the left wall, ball speed after it / (X w)); the next impact, on the right wall at phase
//    theta_{n+1} + pi, is mirrored onto the left wall. Exactly:
//      G = sin(theta_n) + sin(theta_{n+1}) + V_n (theta_{n+1} - theta_n + pi) - D = 0    (flight)
//      V_{n+1} = e V_n + (1 + e) cos(theta_{n+1})                                         (impact)
//    Linearised at (alpha, U) with c = cos(alpha), s = sin(alpha), dG/dtheta_n = c - U,
//    dG/dtheta_{n+1} = c + U = 2c/(1 - e), dG/dV_n = pi:
//      J = [[ e,            -pi (1 - e)/(2 c)             ],
//           [ -e (1 + e) s,  e + pi (1 - e^2) s / (2 c)   ]],   det J = e^2,
//      trace J = T = 2 e + (pi/2) (1 - e^2) tan(alpha),  eigenvalues lambda^2 - T lambda + e^2 = 0.
//    Both |lambda| < 1 iff |T| < 1 + e^2 (det = e^2 < 1), i.e.  -2 r/pi < tan(alpha) < 2/(pi r).
//    The upper bound is tan(psi): the root psi + acos(D/R) violates it (a real eigenvalue > 1), the
//    root psi - acos(D/R) satisfies it; the lower bound gives, with (2), the smallest stable
//    clearance D_min = r (pi^2 - 4)/sqrt(pi^2 + 4 r^2). So the symmetric motion is stable for
//    D_min < D < R (when admissible). At D_min an eigenvalue of the folded map passes -1: the
//    motion becomes asymmetric (still two impacts per drive period, at unequal phases and speeds on
//    the two walls), not a longer period. One drive period is two steps of the folded map: its
//    multipliers are lambda^2.
#pragma once

namespace bagdem {

// The symmetric two-impact periodic motion for given (m, X, w, d, e): the root of (2) that can be
// stable (sections 1 and 4); the saddle root is not reported.
struct TwoImpactMotion {
  bool exists = false;          // (2) has the root and the motion is admissible (section 1)
  bool stable = false;          // exists and max_eigenvalue < 1 (section 4)
  double phase = 0;             // alpha: left-wall impact phase, x = X sin(w t) convention (unit: rad)
  double study_phase = 0;       // phi = alpha + pi/2 in (0, pi): the study's x = X cos(theta) (unit: rad)
  double ball_speed = 0;        // u = |ball velocity| between impacts (unit: m/s)
  double impact_speed = 0;      // relative normal speed before impact, u + X w cos(alpha) (unit: m/s)
  double energy_per_impact = 0; // 2 m r (X w cos alpha)^2 (unit: J)
  double energy_per_cycle = 0;  // two impacts (unit: J)
  double equivalent_damping = 0;  // C_eq = E_cycle / (pi w X^2) (unit: N s/m)
  double effective_mass = 0;    // M_eff = (4/pi) m r sin(phi) cos(phi), section 3 (unit: kg)
  double max_eigenvalue = 0;    // spectral radius of the linearised impact-to-impact map (unit: 1)
};

// m ball mass (kg), X amplitude (m), w angular frequency (rad/s), d clearance (m), e restitution.
// All must be finite, m, X, w, d > 0 and 0 < e < 1 (std::invalid_argument otherwise). Without a
// root (d/X > R) every figure is 0; a root that is not admissible gives exists = false with its
// figures filled in.
TwoImpactMotion two_impact_motion(double m, double X, double w, double d, double e);

// Clearance ratios D = d/X for which the symmetric motion exists and is stable at restitution e
// (0 < e < 1): lo = max(D_min, the admissibility limit), hi = R = sqrt(pi^2 r^2 + 4) (section 4).
// The admissibility limit matters only below e = 0.087 and is found by bisection between D_min and
// R (the motion is admissible at R for every e tried; {0, 0} if it were not).
struct ClearanceRatioRange {
  double lo = 0, hi = 0;  // (unit: 1)
};
ClearanceRatioRange stable_clearance_ratio(double e);

}  // namespace bagdem
