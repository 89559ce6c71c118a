// One steel ball of 20 mm in an 11-mm bag (the ball-size study's 20-mm point; docs/bag.md, Guards),
// settled on the film on the floor of a still box: after settling, the energy budget's residual
// W_gravity + W_cavity - (K + U) - D must change by under 1e-9 J per second (its least-squares slope).
// Reference: 5e-11 J/s for a bag of 100 balls of 4 mm. With the film contact's elastic energy
// counted per contact (one per feature, joined in patches), hits born at positive overlap in the
// film's shallow valleys under the ball made it gain 3.3e-7 J/s; the Euler sum
// (step/surface_features.hpp, euler_terms) counts no contacts.
// The budget is checked with the bending on every step (bag.film.bending_interval = 1, the default): on the
// slower clock (measured at 8 steps; auto gives 4) the impulses of the bending every 8th step keep the settled
// film jiggling, and the membrane damping's work on that jiggle shows as a residual of -9.8e-8 J/s
// (6e-5 of the gravity work per second), the scheme's, not the accounting's
// (test_membrane_bending.cpp: OnASlowerClockTheFilmSwingsAsOnEveryStep).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "bagdem/case/load_case.hpp"
#include "bagdem/step/simulation.hpp"
#include "bag_support.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::energy_balance;
using bagdem::testing::TempDir;

namespace {

// Bearing steel (200 GPa) ball of 20 mm in a capsule bag of 11 mm radius (LDPE, 50 um, damping
// ratio 0.05, nodes 10x heavier), tied to the end walls of a still 80 x 30 x 30 mm box; the
// contacts' restitution 0.5 / 0.3 (film), friction 0.3 / 0.4.
std::string large_ball_bag(int triangles, const std::string& duration, const std::string& film_keys = "") {
  return "[simulation]\nduration = \"" + duration + "\"\nsettle = \"0.05 s\"\ngravity = [0, 0, \"-9.81 m/s^2\"]\nseed = 7\n"
         "[materials.steel]\ndensity = \"7800 kg/m^3\"\nyoungs_modulus = \"200 GPa\"\npoisson_ratio = 0.3\n"
         "[materials.ldpe]\ndensity = \"920 kg/m^3\"\nyoungs_modulus = \"0.25 GPa\"\npoisson_ratio = 0.4\n"
         "[interactions.default]\nrestitution = 0.5\nfriction = 0.3\n"
         "[interactions.steel-ldpe]\nrestitution = 0.3\nfriction = 0.4\n"
         "[cavity]\nkind = \"box\"\nmaterial = \"steel\"\nmin = [\"-40 mm\", \"-15 mm\", \"-15 mm\"]\nmax = [\"40 mm\", \"15 mm\", \"15 mm\"]\n"
         "[bag]\nshape = \"capsule\"\naxis = [1, 0, 0]\nradius = \"11 mm\"\ntriangles = " + std::to_string(triangles) + "\n"
         "[bag.balls]\nmaterial = \"steel\"\ndiameter = \"20 mm\"\ncount = 1\n"
         "[bag.film]\nmaterial = \"ldpe\"\nthickness = \"50 um\"\ndamping_ratio = 0.05\nmass_scaling = 10\n" + film_keys +
         "[[bag.strings]]\nat = \"tail\"\nanchor = [\"-30 mm\", \"0 mm\", \"0 mm\"]\nstiffness = \"200 N/m\"\ndamping = \"0.05 N s/m\"\n"
         "[[bag.strings]]\nat = \"head\"\nanchor = [\"30 mm\", \"0 mm\", \"0 mm\"]\nstiffness = \"200 N/m\"\ndamping = \"0.05 N s/m\"\n";
}

}  // namespace

TEST(BagLargeBall, SettledInATightBagItKeepsItsEnergyBudget) {
  TempDir d;
  d.write("case.toml", large_ball_bag(300, "1 s", "bending_interval = 1\n"));
  const Scene s = load_case(d.str());
  ASSERT_TRUE(s.bag);
  Simulation sim(s);
  const double stored0 = sim.initial_stored_energy();
  // The residual's least-squares slope over the last 40% of the run (the ball still settles before:
  // its kinetic energy falls from 4e-7 to 3e-7 J between 55% and 60%), sampled every 100 steps.
  const std::uint64_t steps = s.total_steps(), settled = steps * 3 / 5;
  double kinetic = 0, St = 0, Sr = 0, Stt = 0, Str = 0, n = 0, time_settled = 0;
  for (std::uint64_t k = 1; k <= steps; ++k) {
    sim.step();
    if (k == settled) time_settled = sim.time();
    if (k <= settled || k % 100 != 0) continue;
    const EnergySample e = sim.energy();
    const double t = sim.time(), r = energy_balance(e, stored0).residual;
    kinetic = std::max(kinetic, e.kinetic);
    St += t, Sr += r, Stt += t * t, Str += t * r, n += 1;
  }
  const double rate = (n * Str - St * Sr) / (n * Stt - St * St);
  const EnergySample end = sim.energy();
  std::printf("  %zu triangles, %.2f edges across; %.3g s to %.3g s: residual changes by %.3e J/s; largest K %.3e J; "
              "W_gravity %.3e J, D %.3e J\n",
              s.bag->rest.triangles.size(), 0.02 / s.bag->mean_edge, time_settled, sim.time(), rate, kinetic, end.work_gravity,
              end.dissipated());
  EXPECT_LT(std::abs(rate), 1e-9);
}
