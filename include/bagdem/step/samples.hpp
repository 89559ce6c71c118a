// What the stepper reports between steps, besides the particles and the energy budget: the cavity's
// samples, the primary structure's state and response, the film's nodes, the pair list's size and
// the stages' clocks.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bagdem/vec3.hpp"

namespace bagdem {

// The cavity over the steps since the last sample (Simulation::take_cavity_sample), all as means
// over those steps, so that every channel is centred on the same time.
struct CavitySample {
  double time = 0;               // mean of the step times (unit: s)
  Vec3 position = Vec3::Zero();  // (unit: m)
  Vec3 velocity = Vec3::Zero();  // (unit: m/s)
  Vec3 force = Vec3::Zero();     // force the contents exerted on it: impulse / elapsed time (unit: N)
  Vec3 torque = Vec3::Zero();    // about Scene::cavity_reference (unit: N m)
  Vec3 contents_velocity = Vec3::Zero();  // the contents' centre of mass relative to the cavity, at the end (unit: m/s)
};

// Wall-clock time spent in each stage since profiling was switched on (benchmarks).
struct StageTimes {
  double integrate = 0;   // kick_drift + move_cavity + structure + kick (balls and film nodes) (unit: s)
  double neighbours = 0;  // pair list and triangle candidate lists
  double pairs = 0;       // ball-ball contacts
  double walls = 0;       // ball-wall contacts (and the balls' kick, when no later stage adds to their forces)
  double triangles = 0;   // ball-film and ball-STL contacts
  double film = 0;        // membrane, strings, film-wall contacts, loads on the film
  double guards = 0;
  std::uint64_t steps = 0;
};

// The size of the current candidate pair list.
struct PairListSize {
  std::size_t pairs = 0;     // candidate pairs
  std::size_t touching = 0;  // of them in contact at the last step
  std::size_t cross = 0;     // of them across two threads' ranges of balls
};

// The bag's film nodes: point masses (no rotation), integrated like the balls.
struct FilmNodes {
  std::vector<Vec3> x, v, v_pred, f;   // as in Particles (unit: m, m/s, N)
  std::vector<Vec3> f_damp, f_damp_prev;  // membrane damping force, this and the previous step (unit: N)
  std::vector<Vec3> wall_force_prev;   // force of the walls on each node at the previous step (unit: N)
  std::vector<double> mass, inv_mass;  // (unit: kg, 1/kg)
  std::size_t size() const { return x.size(); }
};

// How often the bag's film met itself (bag.film.self_contact): the steps at which two of its nodes'
// spheres touched, and the most pairs touching at one step.
struct FilmSelfContact {
  std::uint64_t steps = 0, most = 0;
};

// The primary structure (scene.primary): its state (structure/primary.hpp's generalized coordinates).
struct StructureState {
  std::vector<double> q, v, v_pred, a;  // generalized coordinates and their rates
  std::vector<double> damping_prev;     // C v_pred at the last step (trapezoidal tallies)
  std::vector<double> load_prev;        // generalized load of the contents at the last step
  struct Scalars {
    double phase = 0;          // harmonic drive: phase of the force F sin(phase) (unit: rad)
    double omega = 0;          // harmonic drive: circular frequency (unit: rad/s)
    double force = 0;          // external force at x_f at the last step (unit: N)
    bool released = false;     // settling is over: the structure moves
    double work_external = 0;  // cumulative work of the external force (unit: J)
    double work_contents = 0;  // cumulative work of the contents' load on the structure (unit: J)
    double dissipated = 0;     // cumulative dissipation of the structure's damping (unit: J)
  } scalars;
  Vec3 load_now = Vec3::Zero();  // the contents' load moments (m0, m1, m2) at the last step
};

// The structure's response now.
struct StructureResponse {
  double displacement = 0, velocity = 0, acceleration = 0;  // at x_a along e (unit: m, m/s, m/s^2)
  double force = 0;      // external force at x_f (unit: N)
  double phase = 0;      // drive phase (unit: rad)
  double cavity = 0;     // cavity displacement along e (unit: m)
  double load = 0;       // transverse force of the contents on the cavity (unit: N)
};

}  // namespace bagdem
