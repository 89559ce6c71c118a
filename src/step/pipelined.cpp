// Pipelined steps: advance() on several threads without a meeting at every step.
//
// In the fused step (fused_contacts) each thread does its range's pairs, walls and next drift, and
// the threads meet at the end of every step: when the host interrupts one core (a shared machine
// does, at random), the other waits for it at the meeting. Pipelined steps are many fused steps
// in one parallel region, where the threads wait only for what they read:
//  - the thread of range r computes the cross pairs into r at step s once the ranges below whose
//    balls they reach are at step s (RangeProgress::done); the ranges wait for the records of their
//    own cross pairs as in the fused step (PairState), so a range drifts its balls on only after
//    the ranges above have read them;
//  - whether the pair list holds at step s is known once every range is at step s - 1: the list is
//    renewed a step ahead (Stepper::kSkinStep), so the region ends before the first step at
//    which it must be renewed, and the next step renews it;
//  - each range keeps its own travel (PairState::wake) and rebuild test;
//  - the cavity's motion is computed ahead for all the region's steps;
//  - the guards are checked per range and step; a failing step ends the region for all ranges
//    after that step, and the first failing step is reported as the fused step reports it.
// So a thread delayed by an interruption delays the other only when it is a step behind. The same
// operations on every ball in the same order as the fused step: the same bits
// (Determinism.PipelinedStepsEqualFused). The region ends where the balance looks at the clocks
// (SpanBalance's window), at a rebuild and at the end of advance().
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "stepper.hpp"
#include "loops.hpp"

namespace bagdem {

std::uint64_t Stepper::plan_pipelined(std::uint64_t most) {
  pipe_.region_steps = 0;
  if (most == 0) return 0;
  const auto threads = static_cast<std::uint32_t>(std::max(1, omp_get_max_threads()));
  const bool several = p_.size() >= opt_.parallel_balls && ps_.pairs.size() > kParallelMin;
  // Fused steps (the next drift done: ctx_.balls drifted) with nothing that needs all balls at every step:
  // no triangulated surface (the film, STL walls), no structure, no slope of the cavity; and no
  // rebuild due before the first.
  if (!opt_.pipelining || !opt_.fuse || opt_.profile || !mesh_.surfaces.empty() || structure_.couple || structure_.tilt || ctx_.balls != BallKick::drifted || nb_.needs_rebuild ||
      threads < 2 || !several)
    return 0;
  if (ps_.ranges != threads) derive_ranges(threads);
  // Up to the balance's next look at the clocks, and before the step at which the cavity has moved
  // too far for the walls near each ball (move_cavity; that step rebuilds).
  const std::uint64_t most_steps = std::min<std::uint64_t>(most, balance_.steps_to_window());
  pipe_.cavity_path.resize(most_steps + 1);
  pipe_.wall_path.resize(most_steps);
  pipe_.cavity_path[0] = cavity_.now;
  std::uint64_t steps = 0;
  for (; steps < most_steps; ++steps) {
    const CavityState c = cavity_at(scene_, structure_, static_cast<double>(step_ + steps + 1) * scene_.dt);
    if ((c.position - cavity_.pos_at_build).norm() > 0.5 * scene_.skin) break;
    pipe_.cavity_path[steps + 1] = c;
    pipe_.wall_path[steps] = rigid_motion(pipe_.cavity_path[steps], c);
  }
  pipe_.region_steps = steps;
  return steps;
}

void Stepper::pipelined_region() {
  const std::uint64_t steps = pipe_.region_steps;
  pipe_.region_travel = nb_.travel;
  for (RangeProgress& g : pipe_.progress) {
    g.done.store(0, std::memory_order_relaxed);
    g.travel[0] = g.cross = nb_.travel;
    g.near[0] = nb_.near_edge;
    g.far = nb_.far_check_at;
    g.step = 0;
    g.failed = kNever;
  }
  pipe_.stop_before.store(nb_.near_edge ? 1 : steps);  // near the edge now: the step after the first rebuilds
  pair_contacts(wall_stage(), drift_stage(true), steps);

  std::uint64_t failed = kNever;
  for (const RangeProgress& g : pipe_.progress) failed = std::min(failed, g.failed);
  if (failed != kNever) {
    // The state the guards report from, as after that step of fused steps.
    StageFold f;
    double step = 0;
    for (const RangeProgress& g : pipe_.progress)
      if (g.failed == failed) f.merge(g.fold), step = std::max(step, g.step);
    step_ += failed + 1;
    pipe_.pipelined_steps += failed + 1;
    cavity_.prev = pipe_.cavity_path[failed];
    cavity_.now = pipe_.cavity_path[failed + 1];
    guard_.overlap_excess = f.excess;
    guard_.min_boundary_distance = f.min_dist;
    guard_.all_finite = f.finished_finite;
    nb_.largest_step = step;
    guards();  // throws: a guard failed
    throw std::logic_error("pipelined steps: a guard failed that guards() does not report");
  }
  // Every range did the same steps. The state as after that many fused steps (step_once).
  const std::uint64_t done = pipe_.progress[0].done.load(std::memory_order_relaxed);
  StageFold last;
  double travel = nb_.travel, slack = HUGE_VAL, step = 0;
  bool near_before = false, near_now = false;
  for (std::size_t r = 0; r < pipe_.progress.size(); ++r) {
    const RangeProgress& g = pipe_.progress[r];
    last.merge(g.fold);
    step = std::max(step, g.step);
    near_before = near_before || g.near[(done - 1) % 4];
    near_now = near_now || g.near[done % 4];
    // The largest of the scales at the positions the steps end with, the ranges' and the cross
    // pairs' (cross_travel at step `done`): every pair's wake stays a bound (PairState::wake).
    // The cross scale can outgrow every range's travel (half the sum of three or more ranges'
    // growths); had nb_.travel fallen short of it, a cross pair would sleep too long in the steps
    // after (with three ranges, one thin enough for cross pairs to reach across it, that missed
    // contacts: Determinism.PipelinedStepsEqualFused under load). Each range's balls can come near
    // the edge only once its travel has grown by its slack, so once nb_.travel has.
    travel = std::max({travel, g.travel[done % 4], cross_travel(r, done)});
    slack = std::min(slack, g.far - g.travel[done % 4]);
  }
  nb_.travel = travel;
  nb_.far_check_at = travel + slack;
  nb_.needs_rebuild = near_before;
  nb_.near_edge = near_now;
  nb_.largest_step = step;
  guard_.overlap_excess = last.excess;
  guard_.min_boundary_distance = last.min_dist;
  guard_.finished_finite = guard_.all_finite = guard_.balls_finite = true;
  for (std::uint64_t s = 0; s < done; ++s) {
    cavity_.move_to(static_cast<double>(step_ + 1) * scene_.dt, pipe_.cavity_path[s + 1]);
    ++step_;
    end_balance();
  }
  pipe_.fused_steps += done;
  pipe_.pipelined_steps += done;
  ps_.regions += done;  // the cross stamps used
  pipe_.region_done = done;
}

// The wake of a cross pair (i in a range q below r, j in r) is set and compared on this scale: the
// travel at the region's start (all ranges' then) plus half the sum of what r's travel and the
// travels of all the ranges whose balls the cross pairs into r reach have grown since. Each ball
// moved at most as much as that sum grew, so the pair's balls closed in by at most twice as much
// as the scale grew: the bound the wake needs (PairState::wake), as nb_.travel is for the pairs of one
// range. It starts where the ranges' travels start, so no scale jumps ahead of the others (it
// would compound from region to region). Rounded up (the sum's few roundings are far below 1e-14).
double Stepper::cross_travel(std::size_t r, std::uint64_t s) const {
  double grown = pipe_.progress[r].travel[s % 4] - pipe_.region_travel;
  for (std::size_t q = ps_.cross_from[r]; q < r; ++q) grown += pipe_.progress[q].travel[s % 4] - pipe_.region_travel;
  return std::nextafter(pipe_.region_travel + 0.5 * grown * (1.0 + 1e-14), HUGE_VAL);
}

void Stepper::end_range_step(std::size_t r, std::uint64_t s) {
  RangeProgress& g = pipe_.progress[r];
  const StageFold& f = g.fold;
  g.step = std::sqrt(f.step2);
  // As end_drift, on the range's balls.
  const double travel = std::nextafter(g.travel[s % 4] + g.step * (1.0 + 1e-14), HUGE_VAL);
  bool near = false;
  if (travel > g.far) {
    const Vec3 *x = p_.x.data(), *at_build = nb_.x_at_build.data();
    double d2 = 0;
    for (std::size_t i = ps_.range_first[r]; i < ps_.range_first[r + 1]; ++i) d2 = std::max(d2, (x[i] - at_build[i]).squaredNorm());
    near = Neighbours::near_edge_of(d2, travel, g.far, scene_.skin);
  }
  g.travel[(s + 1) % 4] = travel;
  g.near[(s + 1) % 4] = near;
  auto stop_before = [this](std::uint64_t step) {
    std::uint64_t now = pipe_.stop_before.load(std::memory_order_relaxed);
    while (step < now && !pipe_.stop_before.compare_exchange_weak(now, step, std::memory_order_acq_rel)) {
    }
  };
  // The guards' tests (guards) on the range's folds.
  if (balls_fail(f.finished_finite, f.excess, f.min_dist, g.step, kSkinStep * scene_.skin)) {
    g.failed = s;
    stop_before(s + 1);
  } else if (near) {
    stop_before(s + 2);  // the list is renewed before step s + 2
  }
  g.done.store(s + 1, std::memory_order_release);
}

}  // namespace bagdem
