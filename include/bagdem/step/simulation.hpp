// A simulation of one scene: the balls, the bag's film, the cavity and the structure, advanced by
// the stepper one time step at a time. A step is the fixed list of stages in src/step/stage.hpp
// (velocity Verlet around the contact stages); this is all that run/ and the tests see of it.
//
// Determinism: every sum runs in a fixed order, so results are bitwise equal for any thread count.
// The balls are held in the stepper's order (spatial, for the threads' caches); per-ball outputs
// are written in the scene's order (in_scene_order).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "bagdem/motion/motion.hpp"
#include "bagdem/particles.hpp"
#include "bagdem/scene.hpp"
#include "bagdem/span_balance.hpp"
#include "bagdem/energy.hpp"
#include "bagdem/step/samples.hpp"

namespace bagdem {

class Stepper;

class Simulation {
 public:
  // Sets the scene up: sorts the balls, builds the pair list, evaluates the forces at rest.
  explicit Simulation(const Scene& scene);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  // ---- time -------------------------------------------------------------------------------------
  void step() { advance(1); }
  // Advances `steps` time steps: the same bits as step() that many times, faster (the kick of one
  // step joins the drift of the next). Read the state between calls, not during.
  void advance(std::uint64_t steps);
  const Scene& scene() const;
  double time() const;
  std::uint64_t steps_done() const;

  // ---- the contents -----------------------------------------------------------------------------
  // The balls in the stepper's order: ball i is the scene's ball input_index()[i].
  const Particles& particles() const;
  Particles& particles();
  const std::vector<std::uint32_t>& input_index() const;
  // A per-ball array of particles() (or of the same length) in the scene's order.
  template <class T>
  std::vector<T> in_scene_order(const std::vector<T>& a) const {
    const std::vector<std::uint32_t>& order = input_index();
    std::vector<T> out(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) out[order[i]] = a[i];
    return out;
  }
  const FilmNodes& film() const;  // the bag's film nodes (empty without a bag)
  FilmSelfContact film_self_contact() const;  // how often the film met itself so far
  std::uint64_t film_wall_stops() const;       // steps at which the walls' stop held a film node so far
  // Velocity of the contents' centre of mass (balls and film nodes) relative to the cavity.
  Vec3 contents_relative_velocity() const;
  // Adds dv to the velocity of every ball and film node (a drop test's launch) (unit: m/s).
  void add_contents_velocity(const Vec3& dv);
  // Scene indices of the bag's balls whose centre lies outside the film now, ascending
  // (generalized winding number; O(balls x triangles): for output-time checks and tests).
  std::vector<std::size_t> balls_outside_bag() const;

  // ---- contacts ---------------------------------------------------------------------------------
  std::size_t contact_count() const;       // pairs and walls closed now
  std::size_t mesh_contact_count() const;  // ball-triangle contacts (film and STL walls) now
  std::uint64_t neighbour_builds() const;
  PairListSize pair_list() const;
  // The (i, j) of the pairs across two threads' ranges, in the stepper's order (tests).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cross_pairs() const;
  // The pair list is renewed when a ball came within kSkinStep x skin of the skin's edge, and a ball
  // that moves more than kSkinStep x skin in one step stops the run.
  static constexpr double kSkinStep = 0.25;

  // ---- the cavity and the structure -------------------------------------------------------------
  const CavityState& cavity() const;
  // The cavity over the steps since the last call, as means over them; resets the sums.
  CavitySample take_cavity_sample();
  const StructureState& structure() const;
  StructureResponse structure_response() const;
  double structure_energy() const;  // kinetic + elastic energy of the structure (unit: J)
  // Harmonic drives: a new drive frequency from the next step on, the force's phase continuous.
  // Call it at a whole cycle of the drive.
  void set_drive_frequency(double hz);
  // Between steps, for a sweep point's start: the structure's state changes from the harmonic A at
  // circular frequency w_a to B at w_b (complex amplitudes of its coordinates against the force's
  // phase, q = Re(Q e^{i theta}), Primary::steady_amplitudes), the rest of its state kept; the
  // contents' places move with the cavity's walls (src/step/structure.cpp, jump_structure).
  void jump_harmonic(const Eigen::VectorXcd& A, double w_a, const Eigen::VectorXcd& B, double w_b);

  // ---- the energy budget ------------------------------------------------------------------------
  double initial_stored_energy() const;  // kinetic + elastic at t = 0, the balance's reference (unit: J)
  EnergySample energy() const;

  // ---- checkpoints: the complete dynamic state as a flat byte image, and its inverse ---------------
  std::vector<char> save_state() const;
  void load_state(const std::vector<char>& image);

  // ---- how the steps run (results are the same bits either way; benchmarks and tests) ------------
  void set_profiling(bool on);  // clock each stage (stage_times); costs about 1% of a small step
  const StageTimes& stage_times() const;
  void set_fusion(bool on);     // contact stages and the next drift in one parallel region (default on)
  std::uint64_t fused_steps() const;
  void set_pipelining(bool on); // many steps in one parallel region on several threads (default on)
  std::uint64_t pipelined_steps() const;
  void set_parallel_balls(std::size_t n);  // from how many balls the ball stages use the threads
  // The threads' spans of balls: moved by the clock; tests move them after every step (window 1,
  // tolerance 0) or cut them where they choose, until the balance moves them.
  void set_balance_window(std::uint32_t steps, double tolerance);
  void set_cuts(std::vector<std::uint32_t> cuts);
  const SpanBalance& balance() const;

 private:
  friend class Dampers;  // steps several simulations together (step/dampers.hpp)
  struct OneOfSeveral {};
  Simulation(const Scene& scene, OneOfSeveral);  // one damper of several (Dampers)
  std::unique_ptr<Stepper> s_;
};

}  // namespace bagdem
