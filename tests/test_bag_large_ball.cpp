// One steel ball of 20 mm in an 11-mm bag (the ball-size study's 20-mm point; docs/bag.md, Guards),
// settled on the film on the floor of a still box: after settling, the energy budget's residual
// W_gravity + W_cavity - (K + U) - D must change by under 1e-9 J per second.
// DISABLED: it fails today (-3.3e-7 J/s, 286 triangles, 4.9 film edges across the ball; at other
// film resolutions, box motions and bag sizes 1e-7 to 2e-5 J/s), against 5e-11 J/s for a bag of 100
// balls of 4 mm. The one-contact-per-feature rule (contact/sphere_triangle.hpp) lets a hit be born
// at positive overlap in the film's shallow valleys under the ball, and all of the gain comes in
// those steps (docs/bag.md, Guards). Enable it with a film contact whose energy does not count
// contacts.
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
std::string large_ball_bag(int triangles, const std::string& duration) {
  return "[simulation]\nduration = \"" + duration + "\"\nsettle = \"0.05 s\"\ngravity = [0, 0, \"-9.81 m/s^2\"]\nseed = 7\n"
         "[materials.steel]\ndensity = \"7800 kg/m^3\"\nyoungs_modulus = \"200 GPa\"\npoisson_ratio = 0.3\n"
         "[materials.ldpe]\ndensity = \"920 kg/m^3\"\nyoungs_modulus = \"0.25 GPa\"\npoisson_ratio = 0.4\n"
         "[interactions.default]\nrestitution = 0.5\nfriction = 0.3\n"
         "[interactions.steel-ldpe]\nrestitution = 0.3\nfriction = 0.4\n"
         "[cavity]\nkind = \"box\"\nmaterial = \"steel\"\nmin = [\"-40 mm\", \"-15 mm\", \"-15 mm\"]\nmax = [\"40 mm\", \"15 mm\", \"15 mm\"]\n"
         "[bag]\nshape = \"capsule\"\naxis = [1, 0, 0]\nradius = \"11 mm\"\ntriangles = " + std::to_string(triangles) + "\n"
         "[bag.balls]\nmaterial = \"steel\"\ndiameter = \"20 mm\"\ncount = 1\n"
         "[bag.film]\nmaterial = \"ldpe\"\nthickness = \"50 um\"\ndamping_ratio = 0.05\nmass_scaling = 10\n"
         "[[bag.strings]]\nat = \"tail\"\nanchor = [\"-30 mm\", \"0 mm\", \"0 mm\"]\nstiffness = \"200 N/m\"\ndamping = \"0.05 N s/m\"\n"
         "[[bag.strings]]\nat = \"head\"\nanchor = [\"30 mm\", \"0 mm\", \"0 mm\"]\nstiffness = \"200 N/m\"\ndamping = \"0.05 N s/m\"\n";
}

}  // namespace

TEST(BagLargeBall, DISABLED_SettledInATightBagItKeepsItsEnergyBudget) {
  TempDir d;
  d.write("case.toml", large_ball_bag(300, "1 s"));
  const Scene s = load_case(d.str());
  ASSERT_TRUE(s.bag);
  Simulation sim(s);
  const double stored0 = sim.initial_stored_energy();
  const std::uint64_t steps = s.total_steps(), half = steps / 2;
  double at_half = 0, time_half = 0, kinetic = 0;
  for (std::uint64_t k = 1; k <= steps; ++k) {
    sim.step();
    if (k == half) at_half = energy_balance(sim.energy(), stored0).residual, time_half = sim.time();
    if (k > half) kinetic = std::max(kinetic, sim.energy().kinetic);
  }
  const EnergySample end = sim.energy();
  const double rate = (energy_balance(end, stored0).residual - at_half) / (sim.time() - time_half);
  std::printf("  %zu triangles, %.2f edges across; %.3g s to %.3g s: residual changes by %.3e J/s; largest K %.3e J; "
              "W_gravity %.3e J, D %.3e J\n",
              s.bag->rest.triangles.size(), 0.02 / s.bag->mean_edge, time_half, sim.time(), rate, kinetic, end.work_gravity,
              end.dissipated());
  EXPECT_LT(std::abs(rate), 1e-9);
}
