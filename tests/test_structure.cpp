// The primary structure carrying the cavity (structure/primary.hpp, src/step/structure.cpp,
// run/stepped_sine.hpp), through case files:
//  - case keys and refusals;
//  - an SDOF without contents (one ball that never touches a wall): the swept receptance against
//    the analytic one, 1/(K - w^2 M + i w C), within 0.5% across the band, and its peak (also
//    recomputed from sweep.csv, `bagdem peaks`);
//  - a beam's free decay in one mode gives that mode's damping ratio;
//  - a rigid mass carried by the cavity shifts the beam's frequencies as the exact (continuous
//    Euler-Bernoulli) lumped-mass result;
//  - coupled energy balance over steady cycles: W_ext = D_structure + D_contents within 1%;
//  - balls at a node of a mode barely change its peak, at an antinode they reduce it.
// Contents are soft (E = 10 MPa) and the structures slow (10-30 Hz) so that each test takes
// seconds: the coupling, not the contact stiffness, is under test here.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/run/runner.hpp"
#include "bagdem/run/stepped_sine.hpp"
#include "bagdem/step/simulation.hpp"
#include "bagdem/structure/modes.hpp"
#include "bagdem/structure/response.hpp"
#include "structure_cases.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::TempDir;
using namespace bagdem::testing::structure_cases;

namespace {

constexpr double kPi = std::numbers::pi;

// Run options writing to d/out, without progress output, on every core.
RunOptions quiet_in(const TempDir& d) { return bagdem::testing::quiet_run(d.path / "out", 0); }

}  // namespace

TEST(PrimaryCase, SdofKeysAreResolvedAndBadOnesRefused) {
  TempDir d;
  const std::string primary = "[primary]\nkind = \"sdof\"\nmass = \"2 kg\"\nstiffness = \"31583 N/m\"\ndamping_ratio = 0.05\n";
  const std::string drive = "\n[excitation]\nkind = \"harmonic\"\namplitude = \"1 N\"\nfrequency = \"20 Hz\"\n";
  const std::string sdof = primary + drive;
  const Scene s = load(d, case_text(sdof + kLoneBall));
  ASSERT_TRUE(s.primary);
  EXPECT_EQ(s.primary->kind, "sdof");
  EXPECT_NEAR(s.primary->natural_frequency[0], std::sqrt(31583.0 / 2) / (2 * kPi), 1e-9);
  EXPECT_NEAR(s.primary->damping_ratio[0], 0.05, 1e-12);
  EXPECT_NEAR(s.primary->damping[0], 2 * 0.05 * std::sqrt(31583.0 * 2), 1e-9);

  EXPECT_NE(input_error(d, case_text(primary + "damping = 3\n" + drive + kLoneBall)).find("primary.damping"), std::string::npos);
  const std::string moving = "[cavity.motion]\nkind = \"harmonic\"\namplitude = \"1 mm\"\nfrequency = \"20 Hz\"\n";
  EXPECT_NE(input_error(d, case_text(sdof + moving + kLoneBall)).find("cavity.motion.kind"), std::string::npos);
  const std::string beam = "[primary]\nkind = \"beam\"\nlength = \"1 m\"\nyoungs_modulus = \"70 GPa\"\nouter_diameter = \"20 mm\"\n"
                           "line_density = \"1 kg/m\"\nends = \"pinned-pinned\"\nattach = \"10 mm\"\nforce_at = \"0.3 m\"\n"
                           "response_at = \"0.3 m\"\n\n[excitation]\nkind = \"none\"\n";
  const std::string e = input_error(d, case_text(beam + kLoneBall));
  EXPECT_NE(e.find("primary.attach"), std::string::npos) << e;  // the 40-mm box sticks out of the beam
  // Without a structure, an [excitation] that drives is refused; kind "none" drives nothing and is
  // allowed (bagdem characterize sets it when it drops the structure).
  EXPECT_NE(input_error(d, case_text("[excitation]\nkind = \"harmonic\"\namplitude = \"1 N\"\nfrequency = \"20 Hz\"\n" +
                                     std::string(kLoneBall)))
                .find("excitation"),
            std::string::npos);
  EXPECT_FALSE(load(d, case_text("[excitation]\nkind = \"none\"\n" + std::string(kLoneBall))).primary);

  // An SDOF moving along x needs no primary.axis (it has none: it takes one normal to its
  // direction); a beam along the default axis x cannot move along x, and says to give the axis.
  // (The SDOF used to fail with "primary.axis must be normal to primary.direction".)
  const Scene along_x = load(d, case_text(primary + "direction = [1, 0, 0]\n" + drive + kLoneBall));
  EXPECT_EQ(along_x.primary->direction, Vec3(1, 0, 0));
  EXPECT_NEAR(along_x.primary->axis.dot(along_x.primary->direction), 0, 1e-15);
  EXPECT_EQ(along_x.primary->dof_names, std::vector<std::string>{"mode 1"}) << "its peak is reported as a beam's mode 1";
  std::string beam_x = beam;
  beam_x.insert(beam_x.find("length ="), "direction = [1, 0, 0]\n");
  const std::string beam_along_x = input_error(d, case_text(beam_x + kLoneBall));
  EXPECT_NE(beam_along_x.find("primary.axis"), std::string::npos) << beam_along_x;
  EXPECT_NE(beam_along_x.find("give primary.axis, the direction along the beam"), std::string::npos) << beam_along_x;
}

// An SDOF without contents: the simulated receptance is the analytic one.
TEST(StructureSdof, SweptReceptanceMatchesTheAnalyticOneWithoutContents) {
  TempDir d;
  const double M = 2, fn = 20, zeta = 0.05, K = M * std::pow(2 * kPi * fn, 2), C = 2 * zeta * std::sqrt(K * M);
  std::ostringstream p;
  p << "[primary]\nkind = \"sdof\"\nmass = " << M << "\nstiffness = " << K << "\ndamping = " << C << "\n\n"
    << "[excitation]\nkind = \"stepped-sine\"\namplitude = \"20 N\"\nband = [\"12 Hz\", \"28 Hz\"]\npoints = 9\n"
    << "steady_tolerance = 1e-4\nmax_cycles = 400\n" << kLoneBall;
  const Scene s = load(d, case_text(p.str(), "duration = \"1 s\""), {"simulation.gravity=[0,0,0]"});
  const RunOptions o = quiet_in(d);
  const SteppedSineReport r = run_stepped_sine(s, o);
  ASSERT_TRUE(r.complete) << r.message;
  double worst = 0;
  for (const SteppedSinePoint& pt : r.points) {
    const double w = 2 * kPi * pt.frequency;
    const std::complex<double> H = 1.0 / std::complex<double>(K - w * w * M, w * C);
    const double err = std::abs(pt.receptance - H) / std::abs(H);
    std::printf("  %.4f Hz: |H| %.6e (analytic %.6e), complex error %.2e, %zu cycles\n", pt.frequency,
                std::abs(pt.receptance), std::abs(H), err, pt.cycles);
    worst = std::max(worst, err);
    EXPECT_TRUE(pt.steady);
  }
  EXPECT_LT(worst, 5e-3);
  // The peak refined from the samples (2 Hz apart, half-power width 2 Hz) is the analytic one, as
  // close as the samples are; `bagdem peaks` recomputes the same from the recorded sweep.csv, and
  // refuses a case whose bare structure is not the run's.
  ASSERT_EQ(r.peaks.size(), 1u);
  const double h_peak = 1 / (2 * zeta * std::sqrt(1 - zeta * zeta) * K);
  EXPECT_NEAR(r.peaks[0].peak, h_peak, 5e-3 * h_peak);
  // The case text gives K and C to 6 digits (the stream's default), so the case's own peak is the
  // analytic one to a few 1e-7 of it.
  EXPECT_NEAR(r.peaks[0].bare_peak, h_peak, 1e-5 * h_peak);
  const std::vector<ModePeak> again = recompute_stepped_sine_peaks(*s.primary, d.path / "out");
  ASSERT_EQ(again.size(), 1u);
  EXPECT_NEAR(again[0].peak, r.peaks[0].peak, 1e-9 * h_peak);
  EXPECT_NEAR(again[0].frequency, r.peaks[0].frequency, 1e-9 * fn);
  EXPECT_EQ(again[0].at_band_edge, r.peaks[0].at_band_edge);
  const Scene other = load(d, case_text(p.str(), "duration = \"1 s\""), {"simulation.gravity=[0,0,0]", "primary.damping=" + std::to_string(2 * C)});
  EXPECT_THROW(recompute_stepped_sine_peaks(*other.primary, d.path / "out"), InputError);
  // Each point after a chain's first starts from the steady state predicted with the contents
  // measured at the point before (excitation.predict; no contact here, so the prediction is exact):
  // it settles in the least cycles a point runs. Without the prediction it runs on while the
  // structure's free vibration from the last frequency decays.
  const std::size_t least = s.primary->stepped_sine->least_cycles();
  std::size_t predicted = 0, carried = 0;
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const bool first = i == 0 || i == 5;  // the chains' first points: 12 Hz, and 22 Hz (the second's block starts there)
    if (!first) EXPECT_EQ(r.points[i].cycles, least) << r.points[i].frequency << " Hz";
    predicted += r.points[i].cycles;
  }
  const Scene off = load(d, case_text(p.str(), "duration = \"1 s\""), {"simulation.gravity=[0,0,0]", "excitation.predict=false"});
  const SteppedSineReport q = run_stepped_sine(off, o);
  ASSERT_TRUE(q.complete) << q.message;
  for (const SteppedSinePoint& pt : q.points) carried += pt.cycles;
  std::printf("  cycles in all: %zu predicted, %zu carried\n", predicted, carried);
  EXPECT_GT(carried, predicted + 5 * (r.points.size() - 2));
}

// A free-free beam swinging on its suspension (0.1 Hz) at 5 mm/s while it is driven between its
// first two modes, without contents: the swing adds about v / (pi f) to each cycle's plain first
// harmonic, 30-40% of the forced response here (without CycleHarmonic the points were off by 19% and
// 24% and never settled in 200 cycles); taken out, the swept receptance is the analytic bare one
// within 0.5% (measured 1e-4).
TEST(StructureBeam, SweptReceptanceIsTheBareOneUnderASlowSwing) {
  TempDir d;
  const std::string keys = "[primary]\nkind = \"beam\"\nlength = \"1 m\"\nyoungs_modulus = 10.1321\nsecond_moment = 1\n"
                           "line_density = \"1 kg/m\"\nends = \"free-free\"\nmodes = 4\nattach = 0.5\nforce_at = 0.13\n"
                           "response_at = 0.13\ndamping_ratio = 0.05\nsuspension_frequency = \"0.1 Hz\"\n\n"
                           "[excitation]\nkind = \"stepped-sine\"\namplitude = \"1 N\"\nfrequencies = [18, 22]\n"
                           "steady_tolerance = 1e-4\nmax_cycles = 200\npredict = false\n";
  Scene s = load(d, case_text(keys + kLoneBall, "duration = \"1 s\""), {"simulation.gravity=[0,0,0]"});
  auto P = std::make_shared<Primary>(*s.primary);
  const double v = 5e-3;
  for (std::size_t k = 0; k < P->size(); ++k)
    if (P->dof_names[k] == "rigid translation") P->v0[static_cast<Eigen::Index>(k)] = v / P->at_response[static_cast<Eigen::Index>(k)];
  s.primary = P;
  const SteppedSineReport r = run_stepped_sine(s, quiet_in(d));
  ASSERT_TRUE(r.complete) << r.message;
  for (const SteppedSinePoint& pt : r.points) {
    const double err = std::abs(pt.receptance - pt.bare) / std::abs(pt.bare);
    const double swing = v / (kPi * pt.frequency) / std::abs(pt.bare);  // the swing's reading, per newton
    std::printf("  %.3f Hz: |H| %.5e m/N, bare %.5e, complex error %.2e (the swing alone would read %.2f of it), %zu cycles\n",
                pt.frequency, std::abs(pt.receptance), std::abs(pt.bare), err, swing, pt.cycles);
    EXPECT_GT(swing, 0.1);
    EXPECT_LT(err, 5e-3);
    EXPECT_TRUE(pt.steady);
  }
}

// The steady state with contents of dynamic stiffness Z at the cavity (Primary::steady_amplitudes):
// a rigid mass m (Z = -w^2 m) is the structure carrying that mass, a dashpot c (Z = i w c) the
// structure with that much more damping.
TEST(StructureSdof, SteadyAmplitudesWithContentsAreThoseOfTheStructureWithThem) {
  const double M = 2, K = 31583, C = 12.6, F = 3, m = 0.3, c = 4.2;
  const Primary p = make_sdof_primary(M, K, C, 0.0);
  for (double hz : {5.0, 20.0, 31.0}) {
    const double w = 2 * kPi * hz;
    const std::complex<double> i(0, 1);
    const std::complex<double> mass = p.steady_amplitudes(F, w, -w * w * m)[0], dashpot = p.steady_amplitudes(F, w, i * w * c)[0];
    EXPECT_NEAR(std::abs(mass - (-i * F) / (K - w * w * (M + m) + i * w * C)), 0.0, 1e-12 * std::abs(mass));
    EXPECT_NEAR(std::abs(dashpot - (-i * F) / (K - w * w * M + i * w * (C + c))), 0.0, 1e-12 * std::abs(dashpot));
  }
}

// Free decay from a displacement in mode 1: the fitted damping ratio is the modal one.
TEST(StructureBeam, FreeDecayOfOneModeGivesItsDampingRatio) {
  TempDir d;
  const std::string p = beam_keys(0.5, "damping_ratio = [0.02, 0.01]\n") +
                        "\n[excitation]\nkind = \"decay\"\nmode = 1\ndisplacement = \"2 mm\"\n" + kLoneBall;
  const Scene s = load(d, case_text(p, "duration = \"3 s\""), {"simulation.gravity=[0,0,0]"});
  EXPECT_NEAR(s.primary->natural_frequency[0], 5.0, 1e-3);
  const RunOptions o = quiet_in(d);
  const RunReport r = run_scene(s, o);
  ASSERT_TRUE(r.complete) << r.message;
  std::printf("  decay: zeta %.6f (modal 0.02), 20-dB time %.4f s (analytic %.4f s)\n", r.decay_zeta, r.decay_time,
              std::log(10.0) / (0.02 * 2 * kPi * 5.0));
  EXPECT_NEAR(r.decay_zeta, 0.02, 0.02 * 0.01);
  EXPECT_NEAR(r.decay_time, std::log(10.0) / (0.02 * 2 * kPi * 5.0 * std::sqrt(1 - 0.0004)) * std::sqrt(1 - 0.0004), 0.02 * r.decay_time);
}

// A rigid mass carried by the cavity: the modal model's frequencies (with its 6 modes) against the
// exact continuous result, and a simulated free decay in the first coupled mode.
TEST(StructureBeam, CavityMassShiftsTheFrequenciesAsTheExactLumpedMass) {
  TempDir d;
  const double m = 0.3, x = 0.3;  // 30% of the beam's mass at x/L = 0.3
  std::ostringstream more;
  more << "cavity_mass = " << m << "\nmodes = 12\n";
  std::string keys = beam_keys(x, "damping_ratio = 0\n");
  keys.replace(keys.find("modes = 6\n"), 10, "");
  const std::string p = keys + more.str() + "\n[excitation]\nkind = \"none\"\n" + kLoneBall;
  const Scene s = load(d, case_text(p, "duration = \"1 s\""), {"simulation.gravity=[0,0,0]"});
  const Primary& P = *s.primary;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(Eigen::MatrixXd(P.stiffness.asDiagonal()), P.mass);
  UniformBeam u{1.0, 10.1321, 1.0, BeamEnds::pinned_pinned};
  const std::vector<double> exact = lumped_mass_frequencies(u, x, m, 3);
  for (int k = 0; k < 3; ++k) {
    const double model = std::sqrt(es.eigenvalues()[k]);
    const double bare = 2 * kPi * P.natural_frequency[static_cast<std::size_t>(k)];
    std::printf("  mode %d: bare %.5f, exact with mass %.5f, modal model %.5f rad/s (%+.3f%%)\n", k + 1, bare,
                exact[static_cast<std::size_t>(k)], model, 100 * (model / exact[static_cast<std::size_t>(k)] - 1));
    EXPECT_NEAR(model, exact[static_cast<std::size_t>(k)], 1e-3 * exact[static_cast<std::size_t>(k)]);
    EXPECT_LT(exact[static_cast<std::size_t>(k)], bare * 0.99);  // the mass lowers each frequency by more than 1%
  }
  // Simulated: released in the first coupled mode's shape, it rings at that frequency.
  Scene s2 = s;
  auto P2 = std::make_shared<Primary>(P);
  P2->q0 = 1e-3 * es.eigenvectors().col(0) / P.at_response.dot(es.eigenvectors().col(0));
  s2.primary = P2;
  Simulation sim(s2);
  std::vector<double> y;
  const auto steps = static_cast<std::size_t>(1.0 / s2.dt);
  for (std::size_t k = 0; k < steps; ++k) {
    sim.step();
    y.push_back(sim.structure_response().displacement);
  }
  const DecayFit f = fit_decay(y, s2.dt);
  std::printf("  simulated ring-down: %.5f Hz against exact %.5f Hz\n", f.damped_frequency, exact[0] / (2 * kPi));
  EXPECT_NEAR(f.damped_frequency, exact[0] / (2 * kPi), 2e-3 * exact[0] / (2 * kPi));
}

// Two-way coupling closes the energy balance: the external force's work per steady cycle goes into
// the structure's damping and the contents' dissipation.
TEST(StructureCoupled, EnergyBalanceOverSteadyCycles) {
  TempDir d;
  const double M = 0.25, fn = 12, zeta = 0.05, K = M * std::pow(2 * kPi * fn, 2);
  std::ostringstream p;
  p << "[primary]\nkind = \"sdof\"\nmass = " << M << "\nstiffness = " << K << "\ndamping_ratio = " << zeta << "\n\n"
    << "[excitation]\nkind = \"stepped-sine\"\namplitude = \"0.5 N\"\nfrequencies = [\"11.5 Hz\", \"12 Hz\"]\n"
    << "steady_tolerance = 0.003\nsteady_cycles = 8\nmin_cycles = 16\nmax_cycles = 200\n" << kBalls;
  const Scene s = load(d, case_text(p.str(), "duration = \"1 s\"\nsettle = \"0.2 s\""));
  const RunOptions o = quiet_in(d);
  const SteppedSineReport r = run_stepped_sine(s, o);
  ASSERT_TRUE(r.complete) << r.message;
  for (const SteppedSinePoint& pt : r.points) {
    std::printf("  %.3f Hz: W_ext %.4e J/cycle = D_structure %.4e + D_contents %.4e; closure %.2e; |Y| %.3g m\n",
                pt.frequency, pt.work_external, pt.dissipated_structure, pt.dissipated_contents, pt.balance,
                std::abs(pt.response));
    EXPECT_LT(std::abs(pt.balance), 0.01);
    EXPECT_GT(pt.dissipated_contents, 0.05 * pt.work_external);  // the contents do dissipate
    // Steady state: work in = dissipation, up to the energy the contents store at the window's ends.
    // The 12 balls move chaotically, so that difference depends on the trajectory: runs perturbed in
    // the last bit of one operation gave 0.07-2.0% (the closure above, which counts the stored
    // energy, stays below 1e-5 in all of them). Tolerance 3%.
    EXPECT_NEAR(pt.work_external, pt.dissipated_structure + pt.dissipated_contents, 0.03 * pt.work_external);
  }
}

// Balls carried at a node of mode 2 (mid-span of the pinned-pinned beam) barely change its peak;
// at an antinode (x/L = 0.25) they reduce it.
TEST(StructureBeam, ContentsAtANodeBarelyChangeThatModeAntinodeReducesIt) {
  // 20 balls of 10 mm (82 g, 16% of the modal mass 0.5 kg) in the 40-mm box; bare peak of mode 2
  // at the antinode about 3 mm (Gamma about 5).
  const char* balls = "[particles.balls]\nmaterial = \"soft\"\ndiameter = \"10 mm\"\ncount = 20\nfill = \"lattice\"\n";
  auto reduction = [&](double attach) {
    TempDir d;
    const std::string p = beam_keys(attach, "damping_ratio = 0.03\n") +
                          "\n[excitation]\nkind = \"stepped-sine\"\namplitude = \"2 N\"\naround_modes = [2]\n"
                          "span = 0.2\npoints = 9\nrefine = 4\nsteady_tolerance = 0.01\nsteady_cycles = 3\nmin_cycles = 6\n"
                          "max_cycles = 120\nstart = \"steady\"\n" + std::string(balls);
    const Scene s = load(d, case_text(p, "duration = \"1 s\"\nsettle = \"0.2 s\""));
    const RunOptions o = quiet_in(d);
    const SteppedSineReport r = run_stepped_sine(s, o);
    EXPECT_TRUE(r.complete) << r.message;
    EXPECT_EQ(r.peaks.size(), 1u);
    for (const SteppedSinePoint& pt : r.points) EXPECT_TRUE(pt.steady) << pt.frequency << " Hz";
    if (r.peaks.empty()) return 0.0;
    std::printf("  contents at x = %.3f m: mode 2 peak %.4g m/N at %.4f Hz (bare %.4g at %.4f Hz): %.2f dB (%.1f%%), %zu points\n",
                attach, r.peaks[0].peak, r.peaks[0].frequency, r.peaks[0].bare_peak, r.peaks[0].bare_frequency,
                r.peaks[0].reduction_db, r.peaks[0].reduction_percent, r.points.size());
    return r.peaks[0].reduction_db;
  };
  const double node = reduction(0.5), antinode = reduction(0.25);
  // The antinode's figure depends on which branch the chaotic impact response settles on (1.8 to
  // 9 dB between variants of the coupling tried): the test asks only for a clear reduction.
  EXPECT_LT(std::abs(node), 0.3);
  EXPECT_GT(antinode, 1.0);
}

// A hammer blow on the SDOF (no contents touch): the response after the blow is the impulse
// response J/(M w_d) e^{-zeta w_n t} sin(w_d t) (a blow short against the period), whose decay the
// run reports.
TEST(StructureSdof, ImpulseResponseAndItsDecay) {
  TempDir d;
  const double M = 1, fn = 25, zeta = 0.03, K = M * std::pow(2 * kPi * fn, 2);
  std::ostringstream p;
  p << "[primary]\nkind = \"sdof\"\nmass = " << M << "\nstiffness = " << K << "\ndamping_ratio = " << zeta << "\n\n"
    << "[excitation]\nkind = \"impulse\"\nimpulse = \"0.01 N s\"\nduration = \"0.1 ms\"\n" << kLoneBall
    << "\n";
  const Scene s = load(d, case_text(p.str(), "duration = \"1.5 s\""), {"simulation.gravity=[0,0,0]", "output.cavity_interval=1e-4"});
  const RunOptions o = quiet_in(d);
  const RunReport r = run_scene(s, o);
  ASSERT_TRUE(r.complete) << r.message;
  const double wn = 2 * kPi * fn, wd = wn * std::sqrt(1 - zeta * zeta);
  // RMS of the impulse response over the run: the integral of x^2 to 1.5 s (numerically, fine grid).
  double s2 = 0;
  const int n = 1500000;
  for (int k = 0; k < n; ++k) {
    const double t = (k + 0.5) * 1.5 / n, x = 0.01 / (M * wd) * std::exp(-zeta * wn * t) * std::sin(wd * t);
    s2 += x * x;
  }
  const double rms_exact = std::sqrt(s2 / n);
  std::printf("  impulse: RMS %.6e m (analytic %.6e), zeta %.5f (0.03), 20-dB time %.4f s (analytic %.4f)\n", r.response_rms,
              rms_exact, r.decay_zeta, r.decay_time, std::log(10.0) / (zeta * wn));
  EXPECT_NEAR(r.response_rms, rms_exact, 0.01 * rms_exact);
  EXPECT_NEAR(r.decay_zeta, zeta, 0.01 * zeta);
  EXPECT_NEAR(r.decay_time, std::log(10.0) / (zeta * wn), 0.01 * r.decay_time);
}

// A band-limited random force on the SDOF: in steady state the RMS response of the multisine is
// a sqrt(sum_k |H(w_k)|^2 / 2) over its lines (the phases do not matter over a whole period).
TEST(StructureSdof, RandomForceGivesTheAnalyticRmsResponse) {
  TempDir d;
  const double M = 1, fn = 25, zeta = 0.1, K = M * std::pow(2 * kPi * fn, 2), C = 2 * zeta * std::sqrt(K * M);
  const double lo = 10, hi = 40, T = 1.0, rms_f = 1.0;
  std::ostringstream p;
  p << "[primary]\nkind = \"sdof\"\nmass = " << M << "\nstiffness = " << K << "\ndamping = " << C << "\n\n"
    << "[excitation]\nkind = \"random\"\nrms = " << rms_f << "\nband = [" << lo << ", " << hi << "]\nperiod = " << T
    << "\nseed = 3\n" << kLoneBall;
  // 0.5 s of transient (6 time constants 1/(zeta w_n)) is left out by starting the measure later:
  // run 2 periods and compare the RMS of the second (from the /structure table).
  const Scene s = load(d, case_text(p.str(), "duration = \"2 s\""), {"simulation.gravity=[0,0,0]", "output.cavity_interval=1e-4"});
  Simulation sim(s);
  const auto steps = static_cast<std::size_t>(std::llround(2.0 / s.dt)), half = steps / 2;
  double s2 = 0;
  for (std::size_t k = 0; k < steps; ++k) {
    sim.step();
    if (k >= half) s2 += std::pow(sim.structure_response().displacement, 2);
  }
  const double r = std::sqrt(s2 / static_cast<double>(steps - half));
  double sum = 0;
  int lines = 0;
  for (int k = static_cast<int>(std::ceil(lo * T)); k <= static_cast<int>(std::floor(hi * T)); ++k, ++lines)
    sum += std::norm(sdof_receptance(M, C, K, 2 * kPi * k / T));
  const double a = rms_f * std::sqrt(2.0 / lines), exact = a * std::sqrt(sum / 2);
  std::printf("  random: RMS response %.6e m over the second period (analytic %.6e, %d lines)\n", r, exact, lines);
  EXPECT_NEAR(r, exact, 0.01 * exact);
}

// The FE route reads stepped sections and lumped masses from the case, and on a uniform beam it
// gives the analytic route's frequencies.
TEST(PrimaryCase, FeBeamAgreesWithTheAnalyticBeamAndReadsMasses) {
  TempDir d;
  const std::string base = "\n[excitation]\nkind = \"none\"\n" + std::string(kLoneBall);
  std::string analytic = beam_keys(0.5) + base, fe = analytic;
  fe.replace(fe.find("kind = \"beam\""), 13, "kind = \"fe-beam\"");
  const Scene a = load(d, case_text(analytic)), b = load(d, case_text(fe));
  ASSERT_EQ(a.primary->size(), b.primary->size());
  for (std::size_t k = 0; k < a.primary->size(); ++k)
    EXPECT_NEAR(b.primary->natural_frequency[k], a.primary->natural_frequency[k], 1e-5 * a.primary->natural_frequency[k]);
  // Two stretches (the second twice as stiff) and a 0.2-kg mass at 0.3 m: frequencies change, and the
  // structure's mass counts the lumped mass.
  std::string stepped = fe;
  const std::string extra = "\n[[primary.segments]]\nto = 0.6\n\n[[primary.segments]]\nto = 1.0\nsecond_moment = 2\n\n"
                            "[[primary.masses]]\nat = 0.3\nmass = 0.2\n";
  const std::size_t at = stepped.find("\n[excitation]");
  stepped.insert(at, extra);
  const Scene c = load(d, case_text(stepped));
  EXPECT_NEAR(c.primary->structure_mass, 1.2, 1e-12);
  EXPECT_NE(c.primary->natural_frequency[0], b.primary->natural_frequency[0]);
  std::printf("  fe-beam: uniform f1 %.6f Hz (analytic %.6f); stepped with a mass %.6f Hz\n",
              b.primary->natural_frequency[0], a.primary->natural_frequency[0], c.primary->natural_frequency[0]);
}

// The shipped pipe case: the bare pipe's first three frequencies (docs/reference-study.md, section 3) and
// the bag's ball count at 8% of its mass.
TEST(PipeCase, BarePipeFrequenciesAndBagMassRatio) {
  const Scene s = load_case(std::string(BAGDEM_CASES_DIR) + "/pipe-beanbag");
  ASSERT_TRUE(s.primary && s.bag);
  std::vector<double> f;
  for (std::size_t k = 0; k < s.primary->size(); ++k)
    if (!s.primary->rigid_body[k]) f.push_back(s.primary->natural_frequency[k]);
  std::printf("  pipe: %.2f, %.2f, %.2f Hz; %zu balls\n", f[0], f[1], f[2], s.bag->balls);
  EXPECT_NEAR(f[0], 85.6, 0.05);
  EXPECT_NEAR(f[1], 235.9, 0.05);
  EXPECT_NEAR(f[2], 462.4, 0.05);
  EXPECT_EQ(s.bag->balls, 102u);  // 0.08 x 0.332 kg / 0.261 g
}

// A coupled run restored from a checkpoint continues bit for bit.
TEST(StructureCoupled, RestoredCheckpointContinuesBitwise) {
  TempDir d;
  std::ostringstream p;
  p << "[primary]\nkind = \"sdof\"\nmass = 0.25\nstiffness = 1421\ndamping_ratio = 0.05\n\n"
    << "[excitation]\nkind = \"harmonic\"\namplitude = \"0.5 N\"\nfrequency = \"12 Hz\"\n" << kBalls;
  const Scene s = load(d, case_text(p.str(), "duration = \"0.2 s\"\nsettle = \"0.05 s\""));
  Simulation a(s);
  const auto settle = static_cast<std::size_t>(std::llround(0.05 / s.dt));
  for (std::size_t k = 0; k < settle + 3000; ++k) a.step();
  Simulation b(s);
  b.load_state(a.save_state());
  for (int k = 0; k < 2000; ++k) a.step(), b.step();
  EXPECT_TRUE(a.save_state() == b.save_state());
  EXPECT_GT(std::abs(a.structure_response().displacement), 1e-4);  // it does move
}

// The walls' motion matches the load's projection, so the work the walls do on the contents and
// the work the contents' load does on the beam cancel: with follow_slope (the cavity turns with the
// beam, the load is taken where it acts) to second order in the cavity's length; without it (the
// cavity translates, the load is taken at x_b) exactly. A 40-mm box near a support of the
// pinned-pinned beam (x_b = 0.08 m, steep slope in mode 1) with balls in it, driven near mode 1.
// (Translating walls with the load taken where it acts disagreed by 5.5e-2 here.)
TEST(StructureBeam, WallsWorkMatchesTheLoadsProjectionWithAndWithoutTheSlope) {
  auto mismatch = [](bool slope) {
    TempDir d;
    const std::string p = beam_keys(0.08, std::string("damping_ratio = 0.05\nfollow_slope = ") + (slope ? "true" : "false") + "\n") +
                          "\n[excitation]\nkind = \"harmonic\"\namplitude = \"3 N\"\nfrequency = \"5 Hz\"\nstart = \"steady\"\n" + kBalls;
    const Scene s = load(d, case_text(p, "duration = \"0.6 s\"\nsettle = \"0.2 s\""));
    Simulation sim(s);
    for (std::uint64_t k = 0; k < s.total_steps(); ++k) sim.step();
    const double walls = sim.energy().work_cavity, load = sim.structure().scalars.work_contents;
    std::printf("  follow_slope %d: work of the walls on the contents %.6e J, of the contents' load on the beam %.6e J, "
                "mismatch %.2e\n", slope, walls, load, std::abs(walls + load) / std::abs(walls));
    return std::abs(walls + load) / std::abs(walls);
  };
  EXPECT_LT(mismatch(true), 1e-3);
  EXPECT_LT(mismatch(false), 1e-6);
}

// Free decay with contents: the structure is held at its initial displacement while the bag of balls
// settles, so at release the walls do not jump into them (no overlap guard fires, the contents'
// first contact forces stay at their settled level).
TEST(StructureBeam, DecayWithSettledContentsStartsWithoutAJump) {
  TempDir d;
  const std::string p = beam_keys(0.5, "damping_ratio = 0.02\n") + "\n[excitation]\nkind = \"decay\"\nmode = 1\ndisplacement = \"8 mm\"\n" + kBalls;
  const Scene s = load(d, case_text(p, "duration = \"0.4 s\"\nsettle = \"0.2 s\""));
  const RunOptions o = quiet_in(d);
  const RunReport r = run_scene(s, o);
  EXPECT_TRUE(r.complete) << r.message;
  EXPECT_GT(r.response_rms, 1e-3);  // it rings
}

// A run with a structure killed and resumed reports the same RMS and decay over the whole run as
// one uninterrupted run (the response before the kill is read back from the partial results).
TEST(StructureSdof, ResumedRunReportsTheWholeRunsResponse) {
  TempDir d;
  std::ostringstream p;
  p << "[primary]\nkind = \"sdof\"\nmass = 1\nstiffness = " << std::pow(2 * kPi * 25, 2) << "\ndamping_ratio = 0.03\n\n"
    << "[excitation]\nkind = \"impulse\"\nimpulse = \"0.01 N s\"\nduration = \"0.1 ms\"\n" << kLoneBall << "\n";
  const Scene s = load(d, case_text(p.str(), "duration = \"0.6 s\""),
                       {"simulation.gravity=[0,0,0]", "output.checkpoint_interval=0.05"});
  RunOptions whole = quiet_in(d);
  whole.out_dir = (d.path / "whole").string();
  const RunReport a = run_scene(s, whole);
  ASSERT_TRUE(a.complete) << a.message;
  RunOptions cut = quiet_in(d);
  cut.stop_after_steps = static_cast<long long>(0.3 / s.dt);  // killed half way: checkpoint at 0.25 s
  EXPECT_FALSE(run_scene(s, cut).complete);
  cut.stop_after_steps = -1;
  cut.resume = true;
  const RunReport b = run_scene(s, cut);
  ASSERT_TRUE(b.complete) << b.message;
  EXPECT_GT(a.response_rms, 0);
  EXPECT_DOUBLE_EQ(b.response_rms, a.response_rms);
  EXPECT_DOUBLE_EQ(b.acceleration_rms, a.acceleration_rms);
  EXPECT_DOUBLE_EQ(b.decay_zeta, a.decay_zeta);
  EXPECT_DOUBLE_EQ(b.decay_time, a.decay_time);
}

// The default sampling of the structure resolves its response, and a coarse one is warned about.
TEST(PrimaryCase, StructureSamplingResolvesTheResponseFrequency) {
  TempDir d;
  std::ostringstream p;
  p << "[primary]\nkind = \"sdof\"\nmass = 1\nstiffness = " << std::pow(2 * kPi * 400, 2) << "\ndamping_ratio = 0.03\n\n"
    << "[excitation]\nkind = \"decay\"\ndisplacement = \"1 mm\"\n" << kLoneBall << "\n";
  const Scene s = load(d, case_text(p.str()), {"simulation.gravity=[0,0,0]"});
  EXPECT_NEAR(s.primary->response_frequency, 400, 1e-3);  // K printed to 6 digits
  EXPECT_LE(s.output.cavity_interval, 1.0 / (40 * 400) * (1 + 1e-6));
  const auto warned = [](const Scene& sc) {
    for (const auto& w : sc.warnings)
      if (w.find("output.cavity_interval") != std::string::npos) return true;
    return false;
  };
  EXPECT_FALSE(warned(s));
  EXPECT_TRUE(warned(load(d, case_text(p.str()), {"simulation.gravity=[0,0,0]", "output.cavity_interval=0.0002"})));
}
