// The stepper behind Simulation (step/simulation.hpp): the state of the contents, the cavity and the
// structure as flat arrays, and the stages of a step (stage.hpp) that advance it. Private to src/step/.
#pragma once
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "bagdem/bag/membrane.hpp"
#include "bagdem/contact/mindlin.hpp"
#include "bagdem/contact/rolling.hpp"
#include "bagdem/contact/surface_law.hpp"
#include "bagdem/neighbour/broad_phase.hpp"
#include "bagdem/neighbour/mesh_candidates.hpp"
#include "bagdem/parallel.hpp"
#include "bagdem/particles.hpp"
#include "bagdem/scene.hpp"
#include "bagdem/span_balance.hpp"
#include "bagdem/energy.hpp"
#include "bagdem/step/samples.hpp"
#include "bagdem/step/simulation.hpp"
#include "bagdem/structure/primary.hpp"
#include "balls.hpp"
#include "cavity_frame.hpp"
#include "cavity_track.hpp"
#include "film.hpp"
#include "guard_values.hpp"
#include "mesh_slot.hpp"
#include "neighbours.hpp"
#include "pair_contacts.hpp"
#include "pipeline.hpp"
#include "stage.hpp"
#include "structure_coupling.hpp"
#include "surface_contacts.hpp"
#include "wall_contacts.hpp"

namespace bagdem {

namespace surface_contacts {
struct Found;
struct EulerTerm;
}  // namespace surface_contacts

class Stepper {
 public:
  explicit Stepper(const Scene& scene);

  void step() { advance(1); }       // advance one time step
  // Advances `steps` time steps, the same bits as step() that many times. Between two of them the
  // balls' second half-kick (the kick stage) is not a pass of its own: it is done in the next step's
  // kick_drift, which applies the same force twice in the same order (v + h F/m, then + h F/m), and
  // the wall stage visits only the balls near a wall or the cavity's bounds (walls_.near_balls). One pass
  // over the balls fewer a step. The state is complete when it returns (and only then: read
  // particles(), energy(), checkpoints between calls). A non-finite velocity is then found one step
  // later than by step().
  void advance(std::uint64_t steps);
  const Scene& scene() const { return scene_; }
  double time() const { return static_cast<double>(step_) * scene_.dt; }
  std::uint64_t steps_done() const { return step_; }
  // The balls in the stepper's order: ball i is the scene's ball input_index()[i]. Set-up sorts
  // scenes of kSpatialOrderMin balls or more spatially (neighbour/spatial_order.hpp); smaller ones
  // keep the scene's order. Recorders write per-ball data in the scene's order (in_scene_order).
  const Particles& particles() const { return p_; }
  Particles& particles() { return p_; }
  const std::vector<std::uint32_t>& input_index() const { return p_.order; }
  // A per-ball array of particles() (or of the same length) in the scene's order.
  template <class T>
  std::vector<T> in_scene_order(const std::vector<T>& a) const {
    std::vector<T> out(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) out[p_.order[i]] = a[i];
    return out;
  }
  const CavityState& cavity() const { return cavity_.now; }
  std::uint64_t neighbour_builds() const { return nb_.builds; }
  const PairState& pair_state() const { return ps_; }
  // The bag's film nodes (empty without a bag).
  const FilmNodes& film() const { return film_; }
  FilmSelfContact film_self_contact() const { return film_.tally.self; }
  std::uint64_t film_wall_stops() const { return film_.tally.wall_stops; }
  // Ball-triangle contacts (film and STL walls) now.
  std::size_t mesh_contact_count() const;
  // Scene indices of the bag's balls whose centre lies outside the film now, ascending (generalized
  // winding number; O(balls x triangles), for output-time checks and tests).
  std::vector<std::size_t> balls_outside_bag() const;

  // Kinetic + elastic energy at t = 0 (the reference of the energy balance) (unit: J).
  double initial_stored_energy() const { return energy0_.stored; }
  // Energy budget now (sums over particles in index order).
  EnergySample energy() const;
  // The cavity over the steps since the last call (take_cavity_sample): means over them.
  void set_profiling(bool on) { opt_.profile = on; }
  // Whether advance() may run the pairs and walls stages and the next step's kick_drift in one parallel region
  // (fused_contacts; default on). Results are the same bits either way; tests compare the two.
  void set_fusion(bool on) { opt_.fuse = on; }
  std::uint64_t fused_steps() const { return pipe_.fused_steps; }
  // Whether advance() may run its steps pipelined on several threads (pipelined_region; default on):
  // the threads stay in one parallel region for many steps and wait only for the ranges next to
  // theirs, not for all at each step. Results are the same bits either way; tests compare the two.
  void set_pipelining(bool on) { opt_.pipelining = on; }
  std::uint64_t pipelined_steps() const { return pipe_.pipelined_steps; }
  // From how many balls the ball stages run on several threads (default kParallelBalls, parallel.hpp).
  // Results are the same bits for any value; tests lower it to run the parallel paths on small scenes.
  void set_parallel_balls(std::size_t n) { opt_.parallel_balls = n; }
  // How the threads' spans of the ball stages are balanced (SpanBalance): tests move them after every
  // step (window 1, tolerance 0) to show that results do not depend on where they lie.
  void set_balance_window(std::uint32_t steps, double tolerance) { balance_.set_window(steps, tolerance); }
  // Tests: the threads' ranges cut at `cuts` (one more than the ranges: 0, ..., the ball count),
  // until the balance moves them.
  void set_cuts(std::vector<std::uint32_t> cuts) {
    balance_.reset(std::move(cuts));
    ps_.ranges = 0;
  }
  // The spans' cuts now and how often they moved.
  const SpanBalance& balance() const { return balance_; }
  const StageTimes& stage_times() const { return times_; }
  // Maximum number of triangle features one ball touches at once (surface_contacts.hpp).
  static constexpr std::size_t kMaxMeshContacts = bagdem::kMaxMeshContacts;
  // The Verlet list is renewed one step ahead: before the pairs at a step's positions when, at the
  // step before, a ball was more than skin/2 - kSkinStep x skin from its place at the build; and a
  // ball that moves more than kSkinStep x skin in one step stops the run (guards). So no ball is
  // ever more than skin/2 from its place at the build when its pairs are computed, and on several
  // threads each range of balls knows a step ahead whether the list holds, without waiting for the
  // others (pipelined steps). The price: a renewal after skin/4 of motion instead of skin/2.
  // kSkinStep x skin is 0.2 mm with the default skin of 4 mm balls: 1000 m/s at dt = 2e-7 s.
  static constexpr double kSkinStep = Simulation::kSkinStep;
  CavitySample take_cavity_sample();
  // Number of contacts (pairs and walls) currently closed.
  std::size_t contact_count() const;

  const StructureState& structure() const { return structure_; }
  // Velocity of the contents' centre of mass (balls and film nodes) relative to the cavity, now.
  Vec3 contents_relative_velocity() const;
  // Adds dv to the velocity of every ball and film node (a drop test's launch) (unit: m/s).
  void add_contents_velocity(const Vec3& dv);
  StructureResponse structure_response() const;
  double structure_energy() const;  // kinetic + elastic energy of the structure (unit: J)
  // Harmonic drives: a new drive frequency from the next step on, the force's phase continuous
  // (rigid-body modes move to the new steady state). Call it at a whole cycle of the drive.
  void set_drive_frequency(double hz);
  void jump_harmonic(const Eigen::VectorXcd& A, double w_a, const Eigen::VectorXcd& B, double w_b);
  // Several dampers on one structure (step/dampers.hpp) step together, staged: each its rows before
  // the structure stage (step_contents; last as advance's last step), then, the load of them all
  // shared (share_load: it stays read from there), each its rows from the structure stage on
  // (step_structure). Every damper integrates the same structure with the same load, so each holds
  // the same bits of it.
  void step_contents(bool last);
  const Eigen::VectorXd& contents_load() { return structure_.damper_load(*scene_.primary); }
  void share_load(const Eigen::VectorXd* all) { structure_.all_load = all; }
  void step_structure();
  // The structure's acceleration from the shared load now (after set-up: each damper's set-up saw its own load).
  void restart_structure();
  // Checkpoint support: the complete dynamic state as a flat byte image, and its inverse.
  std::vector<char> save_state() const;
  void load_state(const std::vector<char>& image);

 private:
  using Surface = SurfaceContacts::Surface;
  using RangeProgress = Pipeline::RangeProgress;
  static constexpr std::uint64_t kNever = Pipeline::kNever;

  // One row of the step's table of stages (stages()): what it runs staged, what it runs in a fused
  // step (fusable(): the pairs, the walls and the next step's drift in one parallel region; null:
  // done by another stage of its group), what it runs in a pipelined region, the clock that times it.
  struct StageEntry {
    Stage stage;
    void (Stepper::*run)();
    void (Stepper::*fused)();
    void (Stepper::*pipelined)();  // a pipelined region (several steps): the pairs row's alone
    double StageTimes::*clock;
    bool at_rest;  // a force stage: set-up evaluates the forces at rest with it (StepMode::set_up)
  };
  static std::span<const StageEntry> stages();
  void begin_step(bool last);
  // How run_table runs the rows: one step staged or fused, or a pipelined region of several.
  enum class Schedule { staged, fused, pipelined };
  std::uint64_t run_table(bool last, std::uint64_t most);
  // The staged rows of stages [from, to) (step_contents, step_structure).
  void run_rows(Stage from, Stage to);
  // The rows' functions: each hands its stage's work (a function of its views, or the pair
  // schedule's) to the executor.
  void kick_drift() { kick_drift_stage({ctx_, scene_, p_, balance_, nb_, film_, mesh_, structure_, guard_}); }
  void move_cavity() { move_cavity_stage({scene_, step_, cavity_, structure_, nb_}); }
  void renew_neighbours() { update_neighbours(false); }
  void update_neighbours(bool force_rebuild) {
    neighbours_stage({scene_, frame(), p_, nb_, ps_, walls_, mesh_, film_, cavity_, structure_}, force_rebuild);
  }
  void pair_stage();
  void structure_stage();
  void end_step();
  void wall_contacts();
  void triangle_contacts() { triangle_stage({ctx_, scene_, frame(), p_, film_, mesh_, structure_.cavity_load, guard_}); }
  void film_stage() { bagdem::film_stage({ctx_, scene_, frame(), film_, mesh_, structure_.film_load_moments}); }
  void kick() { kick_stage({ctx_, scene_, p_, balance_, film_, structure_, guard_, kick_balls_here()}); }
  void guards();
  void release_structure();
  // The time since the structure's release at this step's end (stepping) or now (unit: s).
  double since_release(bool stepping) const;
  // The cavity's frame over the step in progress (cavity_frame.hpp), and its answers.
  CavityFrame frame() const { return {scene_, ctx_, cavity_, structure_}; }
  WallMotion rigid_motion() const { return frame().rigid(); }
  WallMotion rigid_motion(const CavityState& prev, const CavityState& now) const { return frame().rigid(prev, now); }
  WallMotion motion_at(const Vec3& x) const { return frame().at(x); }
  Vec3 load_moments(const Vec3& local, const Vec3& force_on_cavity) const { return frame().load_moments(local, force_on_cavity); }
  // A stage over the balls [b0, b1) (drift_span, wall_span, as chosen for the scene's models).
  // cavity: the walls' motion over the step (rigid_motion), which the wall stage reads (with a
  // slope, per ball: motion_at) and the drift does not.
  using BallSpan = void (Stepper::*)(std::size_t b0, std::size_t b1, const WallMotion& cavity, StageFold& fold);
  // kick_drift on balls [b0, b1): Finish: the last step's kick first (advance). end_drift: its results.
  template <bool Finish, bool Rotation, bool Gravity, bool Energy>
  void drift_span(std::size_t b0, std::size_t b1, const WallMotion& cavity, StageFold& fold);
  BallSpan drift_stage(bool finish) const;
  // span over all balls, on the threads' spans (SpanBalance), its folds merged into fold.
  void over_balls(BallSpan span, StageFold& fold);
  // Stages 4, 5 and the next step's 1 in one parallel region (fused_contacts).
  void fused_contacts();
  // ctx_.defer_kick also means no triangulated surface, so no film: no later stage adds to the balls.
  bool fusable() const { return opt_.fuse && !opt_.profile && ctx_.defer_kick; }
  // The pairs stage; with `walls` and `drift` (fused_contacts), each thread's range of balls goes through
  // them once its pairs are done.
  // pipelined > 0: up to that many pipelined steps (pipelined_region), whose count it returns.
  std::uint64_t pair_contacts(BallSpan walls = nullptr, BallSpan drift = nullptr, std::uint64_t pipelined = 0);
  template <bool Tangential, bool Rolling, bool Energy, bool Uniform>
  std::uint64_t pair_contacts_impl(BallSpan walls, BallSpan drift, std::uint64_t pipelined);
  template <class CrossPart, class RangePart>
  std::uint64_t pipelined_pair_steps(const CrossPart& cross_part, const RangePart& range_part);
  // The pair stage's folds into the guards' values (and, fused, the walls' and the drift's).
  void end_pair_stage(const StageFold& fold, bool fused);
  // Plans a pipelined region of up to `most` steps of advance(): how many it may do (0: the scene
  // or the state does not allow one now; the cavity's path computed ahead for them).
  std::uint64_t plan_pipelined(std::uint64_t most);
  // The region plan_pipelined planned (the pairs row's pipelined function): pipe_.region_done steps.
  void pipelined_region();
  // The travel scale of the cross pairs into range r at pipelined step s (pipelined_region).
  double cross_travel(std::size_t r, std::uint64_t s) const;
  // Range r finished pipelined step s: its travel, its rebuild flag, its guards.
  void end_range_step(std::size_t r, std::uint64_t s);
  void derive_ranges(std::uint32_t ranges);
  void end_balance();
  template <bool Tangential, bool Rolling, bool Energy>
  void wall_span(std::size_t b0, std::size_t b1, const WallMotion& cavity, StageFold& fold);
  BallSpan wall_stage() const;
  // The wall stage's results into the guards' values.
  void end_walls(const StageFold& fold);
  template <class IO>
  void state_fields(IO& io);  // checkpoint.cpp: its own fields, then each component's checkpoint()
  // Per-particle sums of the new step start from gravity and zero torque and dissipation.
  void start_sums(std::size_t i) {
    p_.f[i] = scene_.models.gravity ? Vec3(p_.mass[i] * scene_.gravity) : Vec3::Zero();
    p_.t[i].setZero();
    if (scene_.models.energy) p_.tally.step_dissipation[i].setZero();
  }
  double potential_energy() const;
  double largest_overlap_ratio() const;
  // fn(overlap, normal elastic energy (0 on a triangulated surface: mesh_.elastic), tangential,
  // rolling, smaller radius) for every closed contact, pairs then walls (null: not modelled).
  template <class Fn>
  void for_each_contact(Fn&& fn) const;
  double elastic_energy() const;

  const Scene& scene_;
  // The components: each owns its arrays (one header each, named after it).
  Balls p_;                    // balls.hpp
  PairContacts ps_;            // pair_contacts.hpp
  Neighbours nb_;              // neighbours.hpp: renews ps_'s list
  WallContacts walls_;         // wall_contacts.hpp
  SurfaceContacts mesh_;       // surface_contacts.hpp: the film's and STL walls' triangles
  Film film_;                  // film.hpp
  StructureCoupling structure_;  // structure_coupling.hpp
  CavityTrack cavity_;         // cavity_track.hpp
  // Wall slot of ball p on wall w (WallContacts::hist).
  std::size_t wall_slot(std::size_t p, std::size_t w) const { return walls_.slot(p, w, p_.size()); }

  // The step in progress and the schedules.
  StepContext ctx_;            // what the stages of the step in progress share
  std::uint64_t step_ = 0;
  GuardValues guard_;          // guard_values.hpp
  Pipeline pipe_;              // pipeline.hpp
  // The threads' spans of the ball stages: the pair stage's ranges (PairState), kick_drift's (and
  // kick's) and the wall stage's. One set of cuts for the three, so that a thread's balls stay in
  // its core's cache from stage to stage (with a set per stage the cuts chased each other and two
  // threads were slower than one); moved by the three stages' summed times (SpanBalance).
  SpanBalance balance_;
  struct Options {
    bool profile = false;
    bool fuse = true;                              // set_fusion
    bool pipelining = true;                        // set_pipelining
    std::size_t parallel_balls = kParallelBalls;   // set_parallel_balls
  } opt_;
  StageTimes times_;
  // The energy budget's reference (budget.cpp).
  struct EnergyReference {
    double potential = 0;      // gravity potential energy at t = 0 (unit: J)
    double stored = 0;         // kinetic + elastic energy at t = 0 (unit: J)
    double contents_mass = 0;  // balls and film nodes (unit: kg)
  } energy0_;
  // The kick stage is done for the balls inside the walls stage when no later stage adds to their
  // forces (no triangulated surface): one pass over them fewer. Not in set-up mode.
  bool kick_balls_here() const { return mesh_.surfaces.empty() && ctx_.stepping(); }
};

}  // namespace bagdem
