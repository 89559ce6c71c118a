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
#include "bagdem/step/energy.hpp"
#include "bagdem/step/samples.hpp"
#include "bagdem/step/simulation.hpp"
#include "bagdem/structure/primary.hpp"
#include "mesh_slot.hpp"
#include "pair_state.hpp"
#include "stage.hpp"

namespace bagdem {

class Stepper {
 public:
  explicit Stepper(const Scene& scene);

  void step() { advance(1); }       // advance one time step
  // Advances `steps` time steps, the same bits as step() that many times. Between two of them the
  // balls' second half-kick (the kick stage) is not a pass of its own: it is done in the next step's
  // kick_drift, which applies the same force twice in the same order (v + h F/m, then + h F/m), and
  // the wall stage visits only the balls near a wall or the cavity's bounds (near_balls_). One pass
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
  const std::vector<std::uint32_t>& input_index() const { return order_; }
  // A per-ball array of particles() (or of the same length) in the scene's order.
  template <class T>
  std::vector<T> in_scene_order(const std::vector<T>& a) const {
    std::vector<T> out(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) out[order_[i]] = a[i];
    return out;
  }
  const CavityState& cavity() const { return cavity_; }
  std::uint64_t neighbour_builds() const { return builds_; }
  const PairState& pair_state() const { return ps_; }
  // The bag's film nodes (empty without a bag).
  const FilmNodes& film() const { return film_; }
  // Ball-triangle contacts (film and STL walls) now.
  std::size_t mesh_contact_count() const;
  // Scene indices of the bag's balls whose centre lies outside the film now, ascending (generalized
  // winding number; O(balls x triangles), for output-time checks and tests).
  std::vector<std::size_t> balls_outside_bag() const;

  // Kinetic + elastic energy at t = 0 (the reference of the energy balance) (unit: J).
  double initial_stored_energy() const { return kinetic_elastic0_; }
  // Energy budget now (sums over particles in index order).
  EnergySample energy() const;
  // The cavity over the steps since the last call (take_cavity_sample): means over them.
  void set_profiling(bool on) { profile_ = on; }
  // Whether advance() may run the pairs and walls stages and the next step's kick_drift in one parallel region
  // (fused_contacts; default on). Results are the same bits either way; tests compare the two.
  void set_fusion(bool on) { fuse_ = on; }
  std::uint64_t fused_steps() const { return fused_steps_; }
  // Whether advance() may run its steps pipelined on several threads (run_pipelined; default on):
  // the threads stay in one parallel region for many steps and wait only for the ranges next to
  // theirs, not for all at each step. Results are the same bits either way; tests compare the two.
  void set_pipelining(bool on) { pipelining_ = on; }
  std::uint64_t pipelined_steps() const { return pipelined_steps_; }
  // From how many balls the ball stages run on several threads (default kParallelBalls, parallel.hpp).
  // Results are the same bits for any value; tests lower it to run the parallel paths on small scenes.
  void set_parallel_balls(std::size_t n) { parallel_balls_ = n; }
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
  // Maximum number of triangle features one ball touches at once.
  static constexpr std::size_t kMaxMeshContacts = 16;
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
  // Checkpoint support: the complete dynamic state as a flat byte image, and its inverse.
  std::vector<char> save_state() const;
  void load_state(const std::vector<char>& image);

 private:
  template <bool, bool, bool, bool>
  friend struct PairKernel;  // pair_kernel.hpp: the pairs stage's work, on the stepper's arrays
  template <bool, bool, bool>
  friend struct WallKernel;  // walls.cpp: the walls stage's work
  // One row of the step's table of stages (stages()): what it runs, the clock that times it.
  struct StageEntry {
    Stage stage;
    void (Stepper::*run)();
    double StageTimes::*clock;
  };
  static std::span<const StageEntry> stages();
  void begin_step(bool last);
  void step_once(bool last);
  // The stages that are not a function of their own elsewhere.
  void renew_neighbours();
  void pair_stage();
  void structure_stage();
  void end_step();
  void kick_drift();
  void move_cavity();
  void cavity_to(double t, const CavityState& c);  // the cavity at time t is c (and its sums)
  void update_neighbours(bool force_rebuild);
  void derive_pair_buffers();
  void find_near_walls();
  void wall_contacts();
  void triangle_contacts();
  template <bool Tangential, bool Rolling, bool Energy>
  void triangle_contacts_impl();
  void film_stage();
  void kick();
  void guards();
  void set_up_structure();
  void release_structure();
  void release_state(Eigen::VectorXd& q, Eigen::VectorXd& v, double& phase) const;
  void restart_acceleration();
  void bare_state_at(double theta, double w, Eigen::VectorXd& q, Eigen::VectorXd& v) const;
  void steady_rigid(double theta, double w, double sign);
  void structure_drift();
  CavityState structure_cavity() const;
  double external_force(double t_motion) const;
  void structure_forces();
  void structure_kick();
  // The cavity's motion at a lab point x: its displacement, the velocity at the end of the step,
  // the mean velocity over the step and the step's displacement. Without a slope the same for
  // every point (rigid_motion); with one, each adds shear * s (s: the point's axial coordinate).
  struct WallMotion {
    Vec3 pos, vel, half, step;
  };
  WallMotion rigid_motion() const { return rigid_motion(cavity_prev_, cavity_); }
  WallMotion rigid_motion(const CavityState& prev, const CavityState& now) const {
    const Vec3 step = now.position - prev.position;
    return {now.position, now.velocity, ctx_.stepping() ? Vec3(step / ctx_.dt) : now.velocity, step};
  }
  WallMotion motion_at(const Vec3& x) const {
    WallMotion m = rigid_motion();
    if (!tilt_) return m;
    const double s = (x - cavity_.position - scene_.cavity_reference).dot(load_axis_);
    m.pos += s * cavity_.shear;
    m.vel += s * cavity_.shear_rate;
    m.step += s * (cavity_.shear - cavity_prev_.shear);
    if (ctx_.stepping()) m.half = m.step / ctx_.dt;
    return m;
  }
  // Moments (f, f s, f s^2) of the transverse force f = F . e the contents put on the cavity at
  // `local` (cavity frame), s its axial distance from the cavity reference (structure/primary.hpp).
  Vec3 load_moments(const Vec3& local, const Vec3& force_on_cavity) const {
    const double s = (local - scene_.cavity_reference).dot(load_axis_), f = force_on_cavity.dot(load_dir_);
    return {f, f * s, f * s * s};
  }
  // What the ball stages fold over the balls (max, min, and, or: the same for any order and team):
  // the guards' values and the largest step.
  struct StageFold {
    double excess = -1e300;         // pairs and walls: max of overlap - max_overlap x smaller radius (unit: m)
    double min_dist = 1e300;        // walls: min of the centres' distances inside the cavity (unit: m)
    bool kicked_finite = true;      // walls: every velocity finite after the kick done there
    double step2 = 0;               // drift: the largest |x(n+1) - x(n)|^2 of a ball (unit: m^2)
    bool finished_finite = true;    // drift: every velocity finite after the pending kick (Finish)
    void merge(const StageFold& o);
  };
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
  void end_drift(const StageFold& fold);
  bool near_skin_edge();
  // Stages 4, 5 and the next step's 1 in one parallel region (fused_contacts).
  void fused_contacts();
  // ctx_.defer_kick also means no triangulated surface, so no film: no later stage adds to the balls.
  bool fusable() const { return fuse_ && !profile_ && ctx_.defer_kick; }
  // The pairs stage; with `walls` and `drift` (fused_contacts), each thread's range of balls goes through
  // them once its pairs are done.
  // pipelined > 0: up to that many pipelined steps (run_pipelined), whose count it returns.
  std::uint64_t pair_contacts(BallSpan walls = nullptr, BallSpan drift = nullptr, std::uint64_t pipelined = 0);
  template <bool Tangential, bool Rolling, bool Energy, bool Uniform>
  std::uint64_t pair_contacts_impl(BallSpan walls, BallSpan drift, std::uint64_t pipelined);
  // The pair stage's folds into the guards' values (and, fused, the walls' and the drift's).
  void end_pair_stage(const StageFold& fold, bool fused);
  // Up to `most` steps of advance() as pipelined steps; how many it did (0: the scene or the state
  // does not allow them now).
  std::uint64_t run_pipelined(std::uint64_t most);
  // The travel scale of the cross pairs into range r at pipelined step s (run_pipelined).
  double cross_travel(std::size_t r, std::uint64_t s) const;
  // Range r finished pipelined step s: its travel, its rebuild flag, its guards.
  void end_range_step(std::size_t r, std::uint64_t s);
  // Whether balls at most sqrt(d2) from their place at the build are near the skin's edge
  // (kSkinStep); if not, far: the travel (now `travel`) up to which they cannot be.
  bool near_edge(double d2, double travel, double& far) const;
  void derive_ranges(std::uint32_t ranges);
  void end_balance();
  template <bool Tangential, bool Rolling, bool Energy>
  void wall_span(std::size_t b0, std::size_t b1, const WallMotion& cavity, StageFold& fold);
  BallSpan wall_stage() const;
  // The wall stage's results into the guards' values.
  void end_walls(const StageFold& fold);
  template <bool Tangential, bool Rolling, bool Energy>
  Vec3 open_pair(std::size_t k);
  // Ball p against the triangulated surfaces: adds to its force F, torque T and dissipation diss,
  // and the STL walls' share to F_cavity / T_cavity (force on the ball, torque on the cavity).
  template <bool Tangential, bool Rolling, bool Energy>
  void mesh_contacts(std::size_t p, Vec3& F, Vec3& T, Vec3& diss, Vec3& F_cavity, Vec3& T_cavity, Vec3& load,
                     double& excess);
  void set_up_film();
  void set_up_meshes();
  void build_mesh_candidates(const std::vector<Vec3>& balls, const std::vector<Vec3>& film, const Vec3& cavity);
  void find_film_walls_near(const std::vector<Vec3>& film, const Vec3& cavity);
  template <class IO>
  void state_fields(IO& io);  // checkpoint.cpp
  bool meshes_need_rebuild() const;
  template <bool Tangential, bool Energy>
  void film_walls();
  // Film node k against the STL walls: adds to the wall force on it F_wall, the angular impulse on
  // the cavity L, the dissipation (dn, dt) and lowers `deepest` to its signed distance.
  template <bool Tangential, bool Energy>
  void node_mesh_contacts(std::size_t k, Vec3& F_wall, Vec3& L, Vec3& load, double& dn, double& dtg, double& deepest);
  double film_elastic_energy() const;
  // Film node k against a wall or an STL wall (normal n towards the node, overlap): the film-wall
  // law (film.cpp: R* = the film's contact radius, m* = the node's mass) against a surface moving at
  // c_vel (end of step) and c_half (over it), histories in slot `at` of hist. The force on the
  // node; dissipation into dn, dtg; `elastic` (when not null): the Hertz elastic part of the normal force.
  template <bool Tangential, bool Energy>
  BAGDEM_INLINE Vec3 node_contact(std::size_t k, const Vec3& n, double overlap, const PairLaw& law, const Vec3& c_vel, const Vec3& c_half,
                                  ContactHistories& hist, std::size_t at, double& dn, double& dtg, double* elastic = nullptr) {
    ContactGeometry g;
    g.n = n, g.overlap = overlap, g.R_eff = scene_.bag->contact_radius, g.m_eff = film_.mass[k];
    g.arm_i = g.arm_j = 0;
    g.v_rel = film_.v_pred[k] - c_vel;
    g.v_half = film_.v[k] - c_half;
    g.w_half.setZero();
    Vec3 no_torque(0, 0, 0), diss(0, 0, 0);  // a node does not turn (arm 0)
    [[maybe_unused]] double no_tally = 0;
    const Vec3 Fc = surface_contact<Tangential, false, Energy>(g, law, ctx_.dt, Energy ? hist.damping_prev[at] : no_tally,
                                                               Tangential ? &hist.tangential[at] : nullptr, nullptr, no_torque, diss, elastic);
    if constexpr (Energy) dn += diss.x(), dtg += diss.y();
    return Fc;
  }
  // Ball p's motion relative to a point of a surface (a wall, an STL wall, the film) that moves at
  // v_end at the end of the step and at v_half over it: g.v_rel, g.v_half and g.w_half, from g.n,
  // g.arm_i and g.arm_j. Spin: the tangential or rolling role is modelled (else the centre's alone).
  template <bool Spin>
  BAGDEM_INLINE void motion_against_surface(std::size_t p, const Vec3& v_end, const Vec3& v_half, ContactGeometry& g) const {
    if constexpr (Spin) {
      g.v_rel = contact_velocity(p_.v_pred[p], v_end, p_.w_pred[p], Vec3::Zero(), g);
      g.v_half = contact_velocity(p_.v[p], v_half, p_.w[p], Vec3::Zero(), g);
      g.w_half = p_.w[p];
    } else {
      g.v_rel = p_.v_pred[p] - v_end;
      g.v_half = p_.v[p] - v_half;
      g.w_half.setZero();
    }
  }
  // The kick for ball i, with its force F and torque T: v += h F/m, w += h T/I (h = dt/2). Returns
  // whether the new velocity is finite.
  BAGDEM_INLINE bool kick_ball(std::size_t i, const Vec3& F, const Vec3& T, double h, bool rotation) {
    const Vec3 v = p_.v[i] + h * p_.inv_mass[i] * F;
    p_.v[i] = v;
    if (rotation) p_.w[i] += h * p_.inv_inertia[i] * T;
    return std::isfinite(v.squaredNorm());
  }
  // Per-particle sums of the new step start from gravity and zero torque and dissipation.
  void start_sums(std::size_t i) {
    p_.f[i] = scene_.models.gravity ? Vec3(p_.mass[i] * scene_.gravity) : Vec3::Zero();
    p_.t[i].setZero();
    if (scene_.models.energy) tally_.step_dissipation[i].setZero();
  }
  CavityState cavity_at(double t) const;
  double potential_energy() const;
  double largest_overlap_ratio() const;
  // fn(overlap, normal elastic energy (0 on a triangulated surface: mesh_elastic_), tangential,
  // rolling, smaller radius) for every closed contact, pairs then walls (null: not modelled).
  template <class Fn>
  void for_each_contact(Fn&& fn) const;
  double elastic_energy() const;

  const Scene& scene_;
  Particles p_;
  std::vector<std::uint32_t> order_;          // per ball: its index in scene_.particles (input_index)
  ParticleTallies tally_;
  PairState ps_;
  std::unique_ptr<BroadPhase> broad_;
  std::vector<Vec3> x_at_build_;              // positions at the last neighbour build
  // Buffers of the previous pair list, reused by the next rebuild (no allocation once grown).
  struct Spare {
    CandidatePairs pairs;
    ContactHistories hist;
  } spare_;
  // Histories of the wall contacts, per wall then per particle (wall_slot): the balls on one wall
  // of a bed (its floor) come in runs in the stepper's order (spatial_order), so their histories
  // on that wall lie side by side.
  ContactHistories wall_hist_;
  std::size_t wall_slot(std::size_t p, std::size_t w) const { return w * p_.size() + p; }
  std::vector<std::uint32_t> wall_touch_;     // per particle: bit w set = touched wall w at the last step
  // Per particle: bit w set = wall w was within skin of the ball's surface at the last neighbour
  // build. The list holds while no ball and not the cavity moved more than skin/2 since
  // (kick_drift, move_cavity), so the walls not in it cannot be touched: wall_contacts skips them.
  std::vector<std::uint32_t> wall_near_;
  // The balls, ascending, that may touch a wall or leave the cavity's bounds before the next build:
  // a wall near (wall_near_) or the centre within skin of the bounds at the build. The others are
  // skipped by the wall stage when it has nothing else to do for them (advance).
  std::vector<std::uint32_t> near_balls_;
  std::vector<std::uint8_t> near_scratch_;    // find_near_walls: per ball, 1 if in near_balls_ (kept: no allocation in a step)
  Vec3 cavity_pos_at_build_ = Vec3::Zero();   // cavity position and shear at the last build
  Vec3 cavity_shear_at_build_ = Vec3::Zero();
  CavityState cavity_, cavity_prev_;
  StepContext ctx_;                           // what the stages of the step in progress share
  std::uint64_t step_ = 0;
  std::uint64_t builds_ = 0;
  // Sums over the steps of the current cavity sample (take_cavity_sample).
  struct CavitySums {
    std::uint64_t steps = 0;
    double time = 0;                 // sum of step times (unit: s)
    Vec3 position = Vec3::Zero();    // (unit: m)
    Vec3 velocity = Vec3::Zero();    // (unit: m/s)
  } cavity_sums_;
  // ---- triangulated surfaces (surfaces.cpp): the film (surface 0 with a bag), STL walls ----
  struct Surface {
    const TriangleMesh* mesh;   // topology (and, for STL walls, the vertices in the cavity frame)
    bool film;                  // vertices are film_.x (lab frame); otherwise mesh->vertices + cavity position
    int material;
    double reach;               // the film's half thickness, 0 for a wall (unit: m)
  };
  std::vector<Surface> surfaces_;
  std::vector<MeshCandidates> mesh_cand_;     // per surface
  std::vector<MeshSlot> slots_;               // per ball: kMaxMeshContacts slots
  ContactHistories slot_hist_;                // their histories
  std::vector<std::uint8_t> slot_count_;      // per ball
  std::vector<FilmLoad> film_load_;           // per ball slot, this step
  std::vector<double> mesh_elastic_;               // per ball: its surface contacts' elastic energy (euler_terms; unit: J)
  std::vector<std::vector<NodePush>> film_push_;   // per ball: their elastic forces on the film's nodes
  std::vector<Vec3> mesh_force_prev_;         // per ball: force of the STL walls at the last step (unit: N)
  // A ball that cannot touch the film before mesh_travel_ reaches mesh_wake_ (surfaces.cpp).
  bool asleep(std::size_t p) const { return !mesh_wake_.empty() && mesh_travel_ < mesh_wake_[p] && slot_count_[p] == 0; }
  std::vector<double> mesh_wake_;  // per ball (unit: m)
  double mesh_travel_ = 0;         // (unit: m)
  std::vector<std::int8_t> side_;             // per ball: -1 inside the film (or an STL wall), +1 outside
  Vec3 cavity_at_build_ = Vec3::Zero();
  std::vector<Vec3> film_at_build_;
  std::size_t crossed_ = static_cast<std::size_t>(-1);  // a ball found across the film this step
  double crossed_depth_ = 0;                  // how far beyond the film's mid-surface (unit: m)
  std::size_t crossed_surface_ = 0;           // which surface it crossed
  std::vector<MeshCandidates> node_cand_;     // per surface: film nodes' candidate triangles (STL walls)
  std::vector<double> node_reach_;            // per film node: half the film thickness (unit: m)
  std::vector<MeshSlot> node_slots_;          // per film node: kMaxMeshContacts slots on STL walls
  ContactHistories node_slot_hist_;           // their histories (no rolling: a node does not turn)
  std::vector<std::uint8_t> node_slot_count_;
  std::vector<double> node_mesh_elastic_;     // per film node: the elastic energy of its STL-wall contacts (unit: J)
  std::size_t mesh_overflow_ = static_cast<std::size_t>(-1);  // a ball touching more than kMaxMeshContacts features
  // ---- the bag's film (film.cpp) ----
  FilmNodes film_;
  std::unique_ptr<Membrane> membrane_;
  ContactHistories film_wall_hist_;               // per node per wall (no rolling: a node does not turn)
  std::vector<std::uint32_t> film_wall_touch_;    // per node: walls touched at the last step
  std::vector<std::uint32_t> film_wall_near_;    // per node: the walls it may touch (find_film_walls_near)
  struct StringState {
    double damping_prev = 0;              // damping part of the tension at the last step (unit: N)
    Vec3 pull_prev = Vec3::Zero();        // pull on the tie at the last step (unit: N)
  };
  std::vector<StringState> strings_;
  double film_deepest_ = 1e300;                   // smallest distance of a film node inside a wall (unit: m)
  struct FilmTallies {
    double work_cavity = 0;       // work of walls and string anchors on the film (unit: J)
    double diss_normal = 0, diss_tangential = 0;  // film-wall contacts (unit: J)
    double diss_damping = 0;      // membrane and string damping (unit: J)
    Vec3 impulse = Vec3::Zero();  // impulse the film gave the cavity since the last sample (unit: N s)
    Vec3 ang_impulse = Vec3::Zero();  // angular impulse about the cavity reference (unit: N m s)
  } film_tally_;

  // ---- the primary structure (structure.cpp) ----
  StructureState structure_;
  Eigen::VectorXd q_hold_;                    // where the structure is held while the contents settle
  struct {
    Eigen::VectorXd load, damping, total;     // scratch of structure_forces (Q_contents, C v, Q)
  } structure_scratch_;
  bool couple_ = false;                       // a primary structure feels the contents' load
  bool tilt_ = false;                         // the cavity follows the beam's slope too (motion_at)
  double tilt_extent_ = 0;                    // half the cavity's axial extent (unit: m)
  Vec3 load_axis_ = Vec3::Zero(), load_dir_ = Vec3::Zero();  // its axis and transverse direction
  std::vector<Vec3> cavity_load_;             // per ball: load moments on the cavity this step
  Vec3 film_load_moments_ = Vec3::Zero();     // the film's (walls and strings) this step
  std::uint64_t release_step_ = 0;            // the step at which settling ends

  double potential0_ = 0;                     // gravity potential energy at t = 0 (unit: J)
  double kinetic_elastic0_ = 0;               // kinetic + elastic energy at t = 0 (unit: J)
  double contents_mass_ = 0;                  // balls and film nodes (unit: kg)
  bool profile_ = false;
  StageTimes times_;
  std::size_t parallel_balls_ = kParallelBalls;  // set_parallel_balls
  // The threads' spans of the ball stages: the pair stage's ranges (PairState), kick_drift's (and
  // kick's) and the wall stage's. One set of cuts for the three, so that a thread's balls stay in
  // its core's cache from stage to stage (with a set per stage the cuts chased each other and two
  // threads were slower than one); moved by the three stages' summed times (SpanBalance).
  SpanBalance balance_;
  // Per range: the last parallel region of the pair stage in which the cross pairs into the range
  // were computed (PairState; a thread waits on the stamps of the ranges above its own).
  struct alignas(64) CrossStamp {
    std::atomic<std::uint64_t> region{0};
  };
  std::vector<CrossStamp> cross_done_;
  std::uint64_t pair_regions_ = 0;
  // Per range, in pipelined steps (run_pipelined): how far it is, and what the other ranges read of
  // it. Its own thread writes it; the others read it once `done` says it is there.
  static constexpr std::uint64_t kNever = ~std::uint64_t{0};
  struct alignas(64) RangeProgress {
    std::atomic<std::uint64_t> done{0};  // steps of the region it finished: its balls are at step `done`
    double travel[4] = {};    // its balls' travel (as travel_) at step s, slot s % 4 (no range gets more than 2 steps ahead of another)
    bool near[4] = {};        // one of its balls near the skin's edge at step s (kSkinStep), slot s % 4
    double far = 0;           // the travel up to which none of its balls can be near the edge (near_skin_edge)
    double cross = 0;         // the travel scale of the cross pairs into it at its last step (cross_travel)
    double step = 0;          // the largest distance one of its balls moved in its last step (unit: m)
    StageFold fold;           // its folds of the step in progress, then of its last step
    std::uint64_t failed = kNever;  // the step at which its guards failed
  };
  std::vector<RangeProgress> progress_;
  std::atomic<std::uint64_t> stop_before_{0};  // no range starts this pipelined step or a later one
  double region_travel_ = 0;                    // travel_ when the pipelined steps began (cross_travel)
  std::vector<CavityState> cavity_path_;        // the cavity at each pipelined step (0: at the start)
  std::vector<WallMotion> wall_path_;           // the walls' motion over each pipelined step
  bool pipelining_ = true;                      // set_pipelining
  std::uint64_t pipelined_steps_ = 0;
  bool uniform_ = false;                      // all balls of one radius and one material
  // The kick stage is done for the balls inside the walls stage when no later stage adds to their forces (no triangulated
  // surface): one pass over them fewer. Not during set-up (ctx_.dt = 0).
  bool kick_balls_here() const { return surfaces_.empty() && ctx_.stepping(); }
  bool balls_finite_ = true;                  // every ball's velocity finite after that kick
  bool finished_finite_ = true;               // every ball's velocity finite after kick_drift finished a pending kick
  // The pair list is renewed before this step's pairs: a ball was near the skin's edge at the last
  // step (end_drift), or the cavity moved more than skin/2 (move_cavity).
  bool needs_rebuild_ = false;
  bool near_edge_ = false;                    // a ball is more than skin/2 - kSkinStep x skin from its place at the build
  double largest_step_ = 0;                   // the largest distance a ball moved in the last step (unit: m)
  // travel_ up to which no ball can be near the skin's edge (near_skin_edge) (unit: m).
  double far_check_at_ = -1.0;
  bool fuse_ = true;                          // set_fusion
  std::uint64_t fused_steps_ = 0;
  // Since the pair list was installed (derive_pair_buffers): the sum over the steps of the largest
  // distance any ball moved in the step, rounded up, so no ball moved farther (PairState::wake) (unit: m).
  double travel_ = 0;
  bool all_finite_ = true;                    // every velocity finite (kick)
  // Guard results of the last step, kept free of divisions (the ratios go into messages only).
  double overlap_excess_ = 0;       // max over contacts of overlap - max_overlap x smaller radius (unit: m)
  double min_boundary_distance_ = 0;// min over particles of the centre's distance inside the cavity (unit: m)
};

}  // namespace bagdem
