// The stepper: set-up, the table of stages and the ways of running it (stage.hpp). Each stage's
// work is in the file named after it.
#include "stepper.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <span>

#include "bagdem/neighbour/spatial_order.hpp"
#include "bagdem/particles.hpp"
#include "loops.hpp"

namespace bagdem {

Stepper::Stepper(const Scene& scene) : scene_(scene) {
  nb_.broad = make_broad_phase(scene.broad_phase);
  const std::size_t n = scene.particles.size();
  p_.order = spatial_order(scene);
  p_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ParticleInit& q = scene.particles[p_.order[i]];
    const double rho = scene.materials[static_cast<std::size_t>(q.material)].density;
    const double m = sphere_mass(rho, q.radius);
    p_.x[i] = q.x;
    p_.v[i] = q.v;
    p_.w[i] = q.w;
    p_.radius[i] = q.radius;
    p_.mass[i] = m;
    p_.inv_mass[i] = 1.0 / m;
    p_.inv_inertia[i] = 1.0 / (0.4 * m * q.radius * q.radius);
    p_.material[i] = q.material;
  }
  p_.v_pred = p_.v;
  p_.w_pred = p_.w;
  // Balls all alike (one radius, one material): the pair kernel takes R*, m* and the law as constants.
  p_.uniform = n > 0 && std::all_of(scene.particles.begin(), scene.particles.end(), [&](const ParticleInit& q) {
               return q.radius == scene.particles[0].radius && q.material == scene.particles[0].material;
             });
  p_.tally.resize(n);
  const std::size_t nw = scene.walls.size();
  walls_.hist.assign(n * nw, scene.models.tangential, scene.models.rolling, scene.models.energy);
  walls_.touch.assign(n, 0);  // 32 bits: a cavity has at most 32 walls (checked when loading)
  walls_.near.assign(n, 0);
  cavity_.now = cavity_.prev = cavity_at(scene_, structure_, 0.0);
  if (scene_.primary) structure_.set_up(*scene_.primary, n);
  film_.set_up(scene_);
  mesh_.set_up(scene_, p_, film_);
  // The contents' mass, balls then film nodes (the order contents_relative_velocity sums them in).
  for (std::size_t i = 0; i < n; ++i) energy0_.contents_mass += p_.mass[i];
  for (std::size_t k = 0; k < film_.size(); ++k) energy0_.contents_mass += film_.mass[k];
  update_neighbours(true);
  for (std::size_t i = 0; i < n; ++i) start_sums(i);
  ctx_.enter(StepMode::set_up, scene_.dt);  // forces at rest: no history increment, no dissipation
  for (const StageEntry& s : stages())
    if (s.at_rest) (this->*s.run)();
  if (structure_.couple) {
    bagdem::structure_stage(ctx_, *scene_.primary, since_release(false), structure_);  // the contents' load at rest
    structure_.release_step = static_cast<std::uint64_t>(std::llround(scene_.settle / scene_.dt));
    if (structure_.release_step == 0) release_structure();
  }
  energy0_.potential = potential_energy();
  const EnergySample e0 = energy();
  energy0_.stored = e0.kinetic + e0.elastic;
}

void Stepper::advance(std::uint64_t steps) {
  for (std::uint64_t k = 0; k < steps;) k += run_table(k + 1 == steps, k + 1 < steps ? steps - 1 - k : 0);  // the last: not pipelined (its kick)
}

// The step's stages (stage.hpp), in order: what each runs, and the clock that times it.
std::span<const Stepper::StageEntry> Stepper::stages() {
  static constexpr StageEntry table[] = {
      // A pipelined region is the pairs row's alone: the walls, the drift, the cavity's path and the
      // guards of its steps run inside it, and it runs only where the other rows have nothing to do
      // (plan_pipelined: no triangulated surface, no structure; the list holds; the kick deferred).
      // stage            staged                      fused (fusable)             pipelined (many steps)         clock                   at rest
      {Stage::kick_drift, &Stepper::kick_drift, &Stepper::kick_drift, nullptr, &StageTimes::integrate, false},
      {Stage::move_cavity, &Stepper::move_cavity, &Stepper::move_cavity, nullptr, &StageTimes::integrate, false},
      {Stage::neighbours, &Stepper::renew_neighbours, &Stepper::renew_neighbours, nullptr, &StageTimes::neighbours, false},
      {Stage::pairs, &Stepper::pair_stage, &Stepper::fused_contacts, &Stepper::pipelined_region, &StageTimes::pairs, true},  // fused: + walls, next drift
      {Stage::walls, &Stepper::wall_contacts, nullptr, nullptr, &StageTimes::walls, true},
      {Stage::triangles, &Stepper::triangle_contacts, &Stepper::triangle_contacts, nullptr, &StageTimes::triangles, true},
      {Stage::film, &Stepper::film_stage, &Stepper::film_stage, nullptr, &StageTimes::film, true},
      {Stage::structure, &Stepper::structure_stage, &Stepper::structure_stage, nullptr, &StageTimes::integrate, false},
      {Stage::kick, &Stepper::kick, &Stepper::kick, nullptr, &StageTimes::integrate, false},
      {Stage::guards, &Stepper::end_step, &Stepper::end_step, nullptr, &StageTimes::guards, false}};
  return table;
}

void Stepper::begin_step(bool last) {
  ctx_.enter(StepMode::step, scene_.dt);
  ctx_.defer_kick = !last && mesh_.surfaces.empty();
  ctx_.step = step_;
  if (structure_.couple && step_ == structure_.release_step && !structure_.scalars.released) release_structure();
}

// The one executor: the table's rows in order, each its column's function for the schedule. A
// pipelined region when `most` later steps allow one (plan_pipelined: it does that many steps, or
// fewer); else one step, fused (fusable: the pair stage also does the walls and the next step's
// drift, each thread on its range of balls, fused_contacts) or staged. Returns the steps done.
std::uint64_t Stepper::run_table(bool last, std::uint64_t most) {
  Schedule schedule = Schedule::pipelined;
  if (plan_pipelined(most) == 0) {
    begin_step(last);
    schedule = fusable() ? Schedule::fused : Schedule::staged;
  }
  double t = opt_.profile ? omp_get_wtime() : 0.0;
  for (const StageEntry& s : stages()) {
    const auto run = schedule == Schedule::pipelined ? s.pipelined : schedule == Schedule::fused ? s.fused : s.run;
    if (run == nullptr) continue;
    (this->*run)();
    if (opt_.profile) {
      const double now = omp_get_wtime();
      times_.*s.clock += now - t;
      t = now;
    }
  }
  if (opt_.profile) ++times_.steps;
  return schedule == Schedule::pipelined ? pipe_.region_done : 1;
}

void Stepper::run_rows(Stage from, Stage to) {
  for (const StageEntry& s : stages())
    if (s.stage >= from && s.stage < to) (this->*s.run)();
}

void Stepper::step_contents(bool last) {
  begin_step(last);
  run_rows(Stage::kick_drift, Stage::structure);
}

void Stepper::step_structure() {
  run_rows(Stage::structure, static_cast<Stage>(static_cast<int>(Stage::guards) + 1));
}

void Stepper::restart_structure() {
  if (structure_.couple && structure_.scalars.released) structure_.restart_acceleration(*scene_.primary, since_release(false));
}

void Stepper::pair_stage() { pair_contacts(); }
void Stepper::structure_stage() {
  if (structure_.couple) bagdem::structure_stage(ctx_, *scene_.primary, since_release(ctx_.stepping()), structure_);
}
void Stepper::end_step() {
  ++step_;
  guards();
  end_balance();
}

// The threads' spans are moved by the clock (SpanBalance); the pair stage's ranges are cut anew
// where its cuts moved.
void Stepper::end_balance() {
  if (balance_.end_step()) ps_.ranges = 0;
}

}  // namespace bagdem
