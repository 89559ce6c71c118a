// The film against itself (step/film_self.cpp, bag.film.self_contact): each node a sphere that meets
// the spheres of the nodes not its neighbours along an edge.
//  - The energy budget of an undamped shaken bag closes with the film's layers touching (the pair's
//    elastic force is minus the gradient of its energy, counted in the film's elastic energy).
//  - The flagship's bag with 10-mm balls at Gamma 100 (80 Hz, 3.9 mm, seed 2: a point of
//    tools/extremes-bag): without it the film passes through itself at its crushed ends within
//    0.085 s and a ball then faces a layer's outer side (the run stops, "crossed the bag's film");
//    with it the run goes on to 0.1 s, no edge of the film ever cuts a triangle of it
//    (segment-triangle intersection, every 0.5 ms), and the energy budget closes within 1e-2 of its
//    scale (the pair's elastic force is minus the gradient of the energy counted in the film's
//    elastic energy; the run's own balance_error, runner.cpp). Measured: up to 10 cuts from t = 0.047 s
//    and a stop at 0.085 s without; none and a balance error of 7.0e-4 with. The run counts the steps at
//    which the film met itself (Simulation::film_self_contact, summary.json's film_self_steps): some
//    with the contact, none without.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bag_support.hpp"
#include "bagdem/error.hpp"
#include "bagdem/step/simulation.hpp"

using namespace bagdem;
using namespace bagdem::testing;

namespace {

const std::vector<std::string> kGammaHundred = {
    "bag.balls.diameter=\"10 mm\"", "bag.radius=\"11 mm\"", "bag.balls.primary_mass=\"0.332 kg\"",
    "primary={kind=\"prescribed\"}", "excitation={kind=\"none\"}",
    "cavity.motion={kind=\"harmonic\", direction=[0, 1, 0]}", "cavity.motion.amplitude=\"0.00388265942 m\"",
    "cavity.motion.frequency=\"80 Hz\"", "cavity.motion.ramp=\"0.025 s\"", "simulation.duration=\"0.06 s\"",
    "simulation.seed=2"};

struct Outcome {
  bool stopped = false;
  std::string message;
  double t_end = 0;
  std::size_t max_cuts = 0;
  double first_cut_t = -1;
  double balance = NAN;  // the energy balance's relative error at the end
  FilmSelfContact touched;  // the run's count of film-film contacts (summary.json's film_self_*)
};

Outcome run_gamma_hundred(bool self_contact) {
  std::vector<std::string> keys = kGammaHundred;
  keys.push_back(std::string("bag.film.self_contact=") + (self_contact ? "true" : "false"));
  const Scene s = load_case(std::string(BAGDEM_SOURCE_DIR) + "/cases/pipe-beanbag", keys);
  Simulation sim(s);
  const double stored0 = sim.initial_stored_energy();
  Outcome o;
  const auto every = static_cast<std::uint64_t>(std::llround(0.5e-3 / s.dt));
  const auto steps = static_cast<std::uint64_t>(std::llround(0.1 / s.dt));
  try {
    for (std::uint64_t k = 0; k < steps; k += every) {
      sim.advance(every);
      const std::size_t c = film_self_intersections(s.bag->rest, sim.film().x);
      if (c > 0 && o.first_cut_t < 0) o.first_cut_t = sim.time();
      o.max_cuts = std::max(o.max_cuts, c);
    }
  } catch (const RunError& e) {
    o.stopped = true;
    o.message = e.what();
  }
  o.t_end = sim.time();
  o.touched = sim.film_self_contact();
  if (!o.stopped) o.balance = energy_balance(sim.energy(), stored0).relative();
  return o;
}

}  // namespace

TEST(FilmSelf, TheFilmDoesNotPassThroughItselfAtGammaHundred) {
  const Outcome without = run_gamma_hundred(false);
  std::printf("without film-film contact: %s at t = %.4f s; the film first cut itself at t = %.4f s, at most %zu cuts\n",
              without.stopped ? "stopped" : "ran", without.t_end, without.first_cut_t, without.max_cuts);
  const Outcome with = run_gamma_hundred(true);
  std::printf("with film-film contact: %s at t = %.4f s; at most %zu cuts; energy balance error %.3g; the film met itself "
              "at %llu steps, at most %llu node pairs at once\n",
              with.stopped ? "stopped" : "ran", with.t_end, with.max_cuts, with.balance,
              static_cast<unsigned long long>(with.touched.steps), static_cast<unsigned long long>(with.touched.most));
  EXPECT_FALSE(with.stopped) << with.message;
  EXPECT_EQ(with.max_cuts, 0u);
  EXPECT_LT(with.balance, 1e-2);
  // The contact is counted where it acts, and not without it.
  EXPECT_GT(with.touched.steps, 0u);
  EXPECT_GE(with.touched.most, 1u);
  EXPECT_EQ(without.touched.steps, 0u);
  // The scene tests what it claims: without the contact the film does cut itself here.
  EXPECT_GT(without.max_cuts, 0u);
}
