// The pairs stage (stage.hpp): pair contacts, the contact kernel (neighbour search -> contact
// geometry -> contact law; the wall contacts are in walls.cpp). Each configuration of the model switches is compiled
// as its own loop (with_flags), so no switch is tested per contact.
#include "stepper.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "bagdem/contact/hertz.hpp"
#include "bagdem/contact/surface_law.hpp"
#include "loops.hpp"

namespace bagdem {

// Pairs per block of the pair stage (one_block), and candidates per step of its scan for the awake.
constexpr std::size_t kBlock = 128, kScanWidth = 16;
// The pair stage fetches the balls' state ahead (fetch_balls) from this many balls on (below, it
// stays in cache from step to step), when the pairs reach at most this far (a bed in the stepper's
// order: spatial_order).
constexpr std::size_t kFetchAheadMin = 16384, kFetchAheadMax = 4096;

// ---- 4. pair_contacts ---------------------------------------------------------------------------
// The pairs run in (i, j) order and each adds its force to f[i] and f[j] at once, so particle p
// receives its pairs (k, p), k < p ascending, then (p, j) ascending: partner order. On several
// threads each thread does this for its own range of particles, and the pairs across ranges go
// through records first (PairState): the same sums in the same order.
std::uint64_t Stepper::pair_contacts(BallSpan walls, BallSpan drift, std::uint64_t pipelined) {
  const std::size_t threads = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
  const bool several = p_.size() >= parallel_balls_ && ps_.pairs.size() > kParallelMin;
  const auto ranges = static_cast<std::uint32_t>(several ? threads : 1);
  if (ps_.ranges != ranges) derive_ranges(ranges);
  // The contact-law configuration is chosen once here, never inside the loop.
  std::uint64_t done = 0;
  with_flags([&]<bool T, bool R, bool E, bool U>() { done = pair_contacts_impl<T, R, E, U>(walls, drift, pipelined); },
             scene_.models.tangential, scene_.models.rolling, scene_.models.energy, uniform_);
  return done;
}

// The pairs and walls stages and the next step's kick_drift in one parallel region, in advance() when no later stage
// adds to the balls' forces (no film, no STL wall; fusable): each thread does its range's pairs,
// then its walls, then moves its balls on to the next step (their kick and drift). The staged step
// takes three regions (a fork and a join each, and each thread waits at each join for the slowest);
// here the threads meet once, and a thread's lead in one stage makes up for its lag in another.
// Why this is sound: pairs run i < j, so once range r's pairs are done no pair of this step reads
// its balls again (the cross pairs into range r were computed before, and r waited for those out of
// it before its last pairs, PairState): their forces are complete, their walls can be done and they
// can move on. The same operations on every ball in the
// same order as the staged step: the same bits (Determinism.FusedStepEqualsStaged).
// Tried and not kept: the same over pieces of 256 or 1024 balls at a time, so that a piece's state
// is still in cache from its pairs when it drifts. It was slower, not faster: 79-83 ns against
// 74-76 ns per particle-step at 49 000 balls on one thread (the staged passes stream through
// memory, which the prefetchers follow; the pieces break the streams).
void Stepper::fused_contacts() {
  pair_contacts(wall_stage(), drift_stage(true));  // the kick of this step is pending (advance)
  ctx_.drifted = true;
  ++fused_steps_;
}

// A pair contact opened this step: clears its history and returns what it still held
// (closing_tally, when Energy; else zero). Rare, so kept out of line: the pair loop stays small.
template <bool Tangential, bool Rolling, bool Energy>
[[gnu::noinline]] Vec3 Stepper::open_pair(std::size_t k) {
  ps_.touching[k] = 0;
  return ps_.hist.open<Tangential, Rolling, Energy>(k, ctx_.dt, [&] {
    const std::uint32_t i = ps_.first[k], j = ps_.pairs.partner[k];
    const Vec3 n = (p_.x[i] - p_.x[j]).normalized();
    return OpeningMotion{n, p_.v[i] - p_.v[j] - (p_.radius[i] * p_.w[i] + p_.radius[j] * p_.w[j]).cross(n), p_.w[i] - p_.w[j]};
  });
}

void Stepper::end_pair_stage(const StageFold& fold, bool fused) {
  overlap_excess_ = fold.excess;
  if (fused) {
    end_walls(fold);
    end_drift(fold);
  }
}

// Uniform: all balls alike, so their radius, inverse mass and law are the first ball's (the same
// values, so the same results; R* and m* are then loop constants, two divisions fewer per contact).
template <bool Tangential, bool Rolling, bool Energy, bool Uniform>
std::uint64_t Stepper::pair_contacts_impl(BallSpan walls, BallSpan drift, std::uint64_t pipelined) {
  const std::size_t np = ps_.pairs.size();
  const double dt = ctx_.dt;
  const PairLawTable* laws = &scene_.laws;  // a pointer: captured by value where used (pair_lanes)
  const double frac = scene_.max_overlap_fraction;
  const double r0 = np > 0 ? p_.radius[0] : 0.0, im0 = np > 0 ? p_.inv_mass[0] : 0.0;
  const PairLaw* law0 = np > 0 ? &(*laws)(p_.material[0], p_.material[0]) : nullptr;
  // The arrays in locals, not through `this`: a store may alias the members, and the compiler would
  // load each array's address again after every store (the flag stores to `touching` alias anything).
  const Vec3 *x = p_.x.data(), *v = p_.v.data(), *w = p_.w.data(), *v_pred = p_.v_pred.data(), *w_pred = p_.w_pred.data();
  const double *radii = p_.radius.data(), *inv_mass = p_.inv_mass.data();
  const int* material = p_.material.data();
  Vec3 *f = p_.f.data(), *t = p_.t.data(), *diss = tally_.step_dissipation.data();
  const std::uint32_t* first = ps_.first.data();
  const std::uint32_t* partner = ps_.pairs.partner.data();
  std::uint8_t* touching = ps_.touching.data();
  double* damping_prev = ps_.hist.damping_prev.data();
  TangentialHistory* tangential = ps_.hist.tangential.data();
  RollingHistory* rolling = ps_.hist.rolling.data();
  const std::uint32_t* cross = ps_.cross.data();
  PairState::Record* rec = ps_.rec.data();
  Vec3* rec_diss = ps_.rec_diss.data();
  auto radius = [radii, r0](std::uint32_t i) BAGDEM_INLINE_LAMBDA { return Uniform ? r0 : radii[i]; };
  // The contact law on kLanes pairs side by side (surface_contact_lanes): lane l is the pair ks[l]
  // for l < n; the lanes past n repeat the last pair (its histories are written again with the same
  // values, its results go to out[n..kLanes), unused). Each pair's force, torques and dissipation go
  // to out[l] as rows of 4 doubles (x, y, z, unused), its histories are updated. No accumulation here.
  struct alignas(32) Out {
    double F[4], Ti[4], Tj[4], diss[4];
  };
  auto pair_lanes = [=](const std::uint32_t* ks, int n, Out* out, double& excess)
                        BAGDEM_INLINE_LAMBDA {
    std::uint32_t K[kLanes], I[kLanes], J[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      K[l] = ks[std::min(l, n - 1)];
      I[l] = first[K[l]];
      J[l] = partner[K[l]];
    }
    auto gather = [](const auto& a, const std::uint32_t* at) BAGDEM_INLINE_LAMBDA {
      return Lanes{a[at[0]], a[at[1]], a[at[2]], a[at[3]]};  // built whole, not lane by lane (lanes.hpp)
    };
    ContactGeometryT<Lanes> g;
    const Lanes ri = Uniform ? splat<Lanes>(r0) : gather(radii, I), rj = Uniform ? splat<Lanes>(r0) : gather(radii, J);
    sphere_sphere_geometry<Lanes>(gather3(x, I), gather3(x, J), ri, rj, g);
    const Lanes deep = g.overlap - frac * min_of(ri, rj);
    for (int l = 0; l < n; ++l) excess = std::max(excess, deep[l]);
    g.m_eff = Uniform ? splat<Lanes>(1.0 / (im0 + im0)) : 1.0 / (gather(inv_mass, I) + gather(inv_mass, J));
    if constexpr (Tangential || Rolling) {
      const Lanes3 wi = gather3(w, I), wj = gather3(w, J);
      g.v_rel = contact_velocity<Lanes>(gather3(v_pred, I), gather3(v_pred, J), gather3(w_pred, I), gather3(w_pred, J), g);
      g.v_half = contact_velocity<Lanes>(gather3(v, I), gather3(v, J), wi, wj, g);
      g.w_half = wi - wj;
    } else {
      g.v_rel = gather3(v_pred, I) - gather3(v_pred, J);
      g.v_half = gather3(v, I) - gather3(v, J);
    }
    double* damping[kLanes];
    TangentialHistory* th[kLanes];
    RollingHistory* rh[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      damping[l] = Energy ? &damping_prev[K[l]] : nullptr;
      th[l] = Tangential ? &tangential[K[l]] : nullptr;
      rh[l] = Rolling ? &rolling[K[l]] : nullptr;
    }
    auto with_law = [&](const auto& law) BAGDEM_INLINE_LAMBDA {
      const SurfaceLanes c = surface_contact_lanes<Tangential, Rolling, Energy>(g, law, dt, damping, th, rh);
      using Row = double[4];
      auto rows = [out](Row Out::*m) BAGDEM_INLINE_LAMBDA {
        return std::array<double*, kLanes>{out[0].*m, out[1].*m, out[2].*m, out[3].*m};
      };
      to_rows(c.F, splat<Lanes>(0), rows(&Out::F).data());
      if constexpr (Tangential || Rolling) {
        // As surface_contact's torque: -arm_i (n x F_t), then the rolling torque (on j: -arm_j (n x F_t)
        // and the opposite rolling torque).
        to_rows(-(g.arm_i * c.nxFt) + c.roll, splat<Lanes>(0), rows(&Out::Ti).data());
        to_rows(-(g.arm_j * c.nxFt) - c.roll, splat<Lanes>(0), rows(&Out::Tj).data());
      }
      if constexpr (Energy) to_rows(c.diss, splat<Lanes>(0), rows(&Out::diss).data());
    };
    if constexpr (Uniform) {
      with_law(*law0);
    } else {
      const PairLaw* e[kLanes];
      for (int l = 0; l < kLanes; ++l) e[l] = &(*laws)(material[I[l]], material[J[l]]);
      with_law(law_lanes(e));
    }
  };
  auto vec = [](const double* row) BAGDEM_INLINE_LAMBDA { return Vec3(row[0], row[1], row[2]); };
  // A closed pair's force, torques and dissipation onto its particles.
  auto apply = [=](std::size_t k, const Out& o) BAGDEM_INLINE_LAMBDA {
    touching[k] = 1;
    const std::uint32_t i = first[k], j = partner[k];
    const Vec3 F = vec(o.F);
    f[i] += F;
    f[j] -= F;
    if constexpr (Tangential || Rolling) {
      t[i] += vec(o.Ti);
      t[j] += vec(o.Tj);
    }
    if constexpr (Energy) {
      diss[i] += 0.5 * vec(o.diss);
      diss[j] += 0.5 * vec(o.diss);
    }
  };
  // The same into cross pair c's records (-F on j: f - F and f + (-F) are the same bits).
  auto record = [=](std::size_t c, const Out& o) BAGDEM_INLINE_LAMBDA {
    touching[cross[c]] = 1;
    const Vec3 F = vec(o.F);
    rec[2 * c] = {F, Tangential || Rolling ? vec(o.Ti) : Vec3::Zero()};
    rec[2 * c + 1] = {-F, Tangential || Rolling ? vec(o.Tj) : Vec3::Zero()};
    if constexpr (Energy) rec_diss[c] = vec(o.diss);
  };
  // Record e (of cross pair e / 2) onto particle p.
  auto add_record = [=](std::uint32_t p, std::size_t e) BAGDEM_INLINE_LAMBDA {
    f[p] += rec[e].force;
    if constexpr (Tangential || Rolling) t[p] += rec[e].torque;
    if constexpr (Energy) diss[p] += 0.5 * rec_diss[e / 2];
  };
  // Whether pair k touches now: the one test of contact (sphere_sphere's, spheres_apart), and when
  // it may touch at the earliest (PairState::wake): at once when it touches now or touched at the
  // last step (an opened pair's tallies and records are cleared at the next look), else once travel
  // has grown by half its gap, less 1e-9 of the radii's sum, which covers the rounding of the gap
  // (about 1e-16 of it) many times over. travel: travel_, or in pipelined steps the pair's range's
  // (run_pipelined).
  float* wake = ps_.wake.data();
  auto look = [x, first, partner, touching, wake, radius](std::uint32_t k, double travel) BAGDEM_INLINE_LAMBDA {
    const std::uint32_t i = first[k], j = partner[k];
    const double rsum = radius(i) + radius(j);
    const bool now = !spheres_apart(x[i], x[j], rsum);
    const Vec3 d = x[i] - x[j];
    const double gap = std::sqrt(dot(d, d)) - rsum;
    wake[k] = round_down_to_float((now | (touching[k] != 0)) ? travel : travel + 0.5 * gap - 1e-9 * rsum);
    return now;
  };
  // Pair k may touch: its histories are fetched now, while the block's other pairs are looked at,
  // so that they are in cache when the law reads them (pass 2). Closed pairs are a few in a hundred
  // candidates, so the hardware prefetchers do not follow their histories (the history loads were
  // a quarter of the pair stage at 100 000 balls).
  auto fetch_histories = [=](std::uint32_t k) BAGDEM_INLINE_LAMBDA {
    if constexpr (Tangential) prefetch_object(&tangential[k], kTangentialBytes<Energy>);
    if constexpr (Rolling) prefetch_object(&rolling[k]);
  };
  // Pairs [k0, k1) of one range, in four passes:
  //  0. the pairs that may touch (awake: PairState::wake), and in a block that holds any (Cross)
  //     the cross pairs (computed already); in the shaken PD-box bed 18-26% of the candidates;
  //  1. among those, a branch-free scan for the pairs that touch now (`closed`), those that touched
  //     at the last step and are apart now (`opened`) and the cross pairs;
  //  2. the contact law on the closed pairs, kLanes at a time (pair_lanes);
  //  3. in pair order: each closed pair applied, each opened pair closed, each cross pair's record
  //     added to its i.
  auto one_block = [&]<bool Cross>(std::size_t k0, std::size_t k1, std::size_t c0, double travel, double& excess) BAGDEM_INLINE_LAMBDA {
    std::uint32_t awake[kBlock + kScanWidth], closed[kBlock], opened[kBlock], crossing[Cross ? kBlock : 1];
    std::size_t na = 0, nc = 0, no = 0, nx = 0;
    const std::uint8_t* is_cross = ps_.is_cross.data();
    std::size_t scan = k0;
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512BW__)
    // kScanWidth candidates at a time: compare, compress the awake ones' indices, store all
    // kScanWidth (those past na are overwritten or unused; awake has room for them).
    // A float is at most travel exactly when it is at most the largest float not above travel.
    const __m512 tv = _mm512_set1_ps(round_down_to_float(travel));
    for (__m512i at = _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(k0)), _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
         scan + kScanWidth <= k1; scan += kScanWidth, at = _mm512_add_epi32(at, _mm512_set1_epi32(static_cast<int>(kScanWidth)))) {
      __mmask16 m = _mm512_cmp_ps_mask(_mm512_loadu_ps(wake + scan), tv, _CMP_LE_OQ);  // wake <= travel (NaN: not)
      if constexpr (Cross) m |= _mm_test_epi8_mask(_mm_loadu_si128(reinterpret_cast<const __m128i*>(is_cross + scan)),
                                                   _mm_set1_epi8(-1));
      _mm512_storeu_si512(awake + na, _mm512_maskz_compress_epi32(m, at));
      na += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(m)));
    }
#endif
    for (std::size_t k = scan; k < k1; ++k) {
      awake[na] = static_cast<std::uint32_t>(k);
      if constexpr (Cross) {
        na += (wake[k] <= travel) | (is_cross[k] != 0);
      } else {
        na += wake[k] <= travel;
      }
    }
    for (std::size_t a = 0; a < na; ++a) {
      const std::uint32_t k = awake[a];
      closed[nc] = opened[no] = k;
      if constexpr (Cross) {
        // A cross pair was looked at by cross_block (its wake is that stage's).
        const bool cross = is_cross[k] != 0;
        crossing[nx] = k;
        nx += cross;
        if (cross) continue;
      }
      const bool now = look(k, travel);
      fetch_histories(now ? k : static_cast<std::uint32_t>(k0));  // without a branch: the block's first is at hand
      nc += now;
      no += !now & (touching[k] != 0);
    }
    Out out[kBlock + kLanes];  // the last lanes of a block may run past nc
    for (std::size_t a = 0; a < nc; a += kLanes)
      pair_lanes(closed + a, static_cast<int>(std::min<std::size_t>(kLanes, nc - a)), out + a, excess);
    constexpr std::uint32_t kNone = ~0u;
    for (std::size_t a = 0, o = 0, c = 0; a < nc || o < no || c < nx;) {
      const std::uint32_t ka = a < nc ? closed[a] : kNone, ko = o < no ? opened[o] : kNone;
      const std::uint32_t kc = Cross && c < nx ? crossing[c] : kNone;
      if (ka < ko && ka < kc) {
        apply(ka, out[a++]);
      } else if (ko < kc) {
        const Vec3 d = open_pair<Tangential, Rolling, Energy>(ko);
        if constexpr (Energy) {
          diss[first[ko]] += 0.5 * d;
          diss[partner[ko]] += 0.5 * d;
        }
        ++o;
      } else {
        add_record(first[kc], 2 * (c0 + c));  // the block's cross pairs are c0, c0 + 1, ...
        ++c;
      }
    }
  };
  // Cross pairs cs[0, n), n <= kBlock, into their records (zero when apart, the closing tally when
  // just opened).
  auto cross_block = [&](const std::uint32_t* cs, std::size_t n, double travel, double& excess) BAGDEM_INLINE_LAMBDA {
    std::uint32_t closed[kBlock], at[kBlock];
    std::size_t nc = 0;
    for (std::size_t m = 0; m < n; ++m) {
      const std::size_t c = cs[m];
      const std::uint32_t k = cross[c];
      if (wake[k] > travel) continue;  // apart since its last look, which left its records zero
      if (look(k, travel)) {
        fetch_histories(k);
        closed[nc] = k, at[nc++] = static_cast<std::uint32_t>(c);
        continue;
      }
      const Vec3 d = touching[k] != 0 ? open_pair<Tangential, Rolling, Energy>(k) : Vec3::Zero();
      rec[2 * c] = rec[2 * c + 1] = {Vec3::Zero(), Vec3::Zero()};
      if constexpr (Energy) rec_diss[c] = d;
    }
    Out out[kBlock + kLanes];
    for (std::size_t a = 0; a < nc; a += kLanes)
      pair_lanes(closed + a, static_cast<int>(std::min<std::size_t>(kLanes, nc - a)), out + a, excess);
    for (std::size_t a = 0; a < nc; ++a) record(at[a], out[a]);
  };
  // The balls' state ahead of the pairs: at ball i, the balls up to i + reach. In a bed sorted by
  // slabs (spatial_order) ball j is first reached from the slab before its own, about a slab's
  // worth of balls after its last use: far enough for the caches to have lost it, and reached
  // in an order the hardware prefetchers do not follow. Every second ball: a Vec3 is 24 bytes, so
  // each 64-byte line holds the start of one of them.
  const std::size_t nballs = p_.size();
  const bool fetch_ahead = nballs >= kFetchAheadMin && ps_.reach <= kFetchAheadMax;
  auto fetch_balls = [=](std::size_t& ahead, std::size_t upto) BAGDEM_INLINE_LAMBDA {
    upto = std::min(upto, nballs);
    for (; ahead < upto; ahead += 2) {
      prefetch_object(&x[ahead]), prefetch_object(&v[ahead]), prefetch_object(&v_pred[ahead]), prefetch_object(&f[ahead]);
      if constexpr (Tangential || Rolling)
        prefetch_object(&w[ahead]), prefetch_object(&w_pred[ahead]), prefetch_object(&t[ahead]);
    }
  };
  // The histories of the pairs [from, to) that touched at the last step: most of them touch again
  // (a contact lasts many steps), so they are fetched a block ahead of their law.
  auto fetch_touching = [=](std::size_t from, std::size_t to) BAGDEM_INLINE_LAMBDA {
    std::size_t k = from;
#if defined(__AVX512BW__)
    for (; k + 64 <= to; k += 64)
      for (std::uint64_t m = _mm512_test_epi8_mask(_mm512_loadu_si512(touching + k), _mm512_set1_epi8(1)); m != 0; m &= m - 1)
        fetch_histories(static_cast<std::uint32_t>(k + static_cast<std::size_t>(std::countr_zero(m))));
#endif
    for (; k < to; ++k)
      if (touching[k] != 0) fetch_histories(static_cast<std::uint32_t>(k));
  };
  // Pairs [k0, k1) in blocks.
  auto pair_span = [&](std::size_t k0, std::size_t k1, double travel, double& excess) BAGDEM_INLINE_LAMBDA {
    std::size_t ahead = k0 < k1 ? first[k0] + ps_.reach : 0;
    if constexpr (Tangential || Rolling) fetch_touching(k0, std::min(k1, k0 + kBlock));
    for (std::size_t k = k0; k < k1; k += kBlock) {
      const std::size_t end = std::min(k1, k + kBlock);
      if (fetch_ahead) fetch_balls(ahead, first[end - 1] + ps_.reach + 1);
      if constexpr (Tangential || Rolling) fetch_touching(end, std::min(k1, end + kBlock));
      // Most blocks hold no cross pair: they take the scan without the cross test.
      const std::size_t c0 = static_cast<std::size_t>(std::lower_bound(ps_.cross.begin(), ps_.cross.end(), k) - ps_.cross.begin());
      if (c0 < ps_.cross.size() && ps_.cross[c0] < end) {
        one_block.template operator()<true>(k, end, c0, travel, excess);
      } else {
        one_block.template operator()<false>(k, end, c0, travel, excess);
      }
    }
  };
  // Range r in two parts: its particles' records from the ranges below and its pairs up to its
  // first cross pair; then, with the records of its cross pairs at hand (PairState), its other pairs
  // and, fused (fused_contacts), its walls and its drift. With one range the first part is all pairs.
  auto range_head = [&](std::size_t r, double travel, StageFold& fold) BAGDEM_INLINE_LAMBDA {
    for (std::uint32_t e = ps_.j_side_range[r]; e < ps_.j_side_range[r + 1]; ++e)
      add_record(ps_.j_side[e].particle, 2 * std::size_t{ps_.j_side[e].cross} + 1);
    pair_span(ps_.pairs.begin[ps_.range_first[r]], ps_.records_from[r], travel, fold.excess);
  };
  auto range_tail = [&](std::size_t r, double travel, const WallMotion& cavity, StageFold& fold) BAGDEM_INLINE_LAMBDA {
    const std::uint32_t b0 = ps_.range_first[r], b1 = ps_.range_first[r + 1];
    pair_span(ps_.records_from[r], ps_.pairs.begin[b1], travel, fold.excess);
    if (drift != nullptr) {
      (this->*walls)(b0, b1, cavity, fold);
      (this->*drift)(b0, b1, cavity, fold);
    }
  };
  const std::size_t ranges = ps_.ranges;
  if (ranges == 1) {
    StageFold fold;
    const double travel = travel_;
    const WallMotion cavity = rigid_motion();
    auto one_range = [&](std::size_t r, StageFold& f) BAGDEM_INLINE_LAMBDA {
      range_head(r, travel, f);
      range_tail(r, travel, cavity, f);
    };
    run_items(one_range, 0, 1, fold);
    end_pair_stage(fold, drift != nullptr);
    return 0;
  }
  // On several threads, range r's part of a step in two: first the cross pairs into it (their
  // records; PairState), stamped when done; then the range, which waits for the stamps of the
  // ranges above that its cross pairs reach only when its pairs reach the first of them. Each
  // thread does the first part of all its ranges before the second (one range each; the loops
  // cover them all for any team size), so every stamp comes. `stamp` is the step's own value.
  auto cross_part = [&](std::size_t r, double travel, std::uint64_t stamp, StageFold& f) BAGDEM_INLINE_LAMBDA {
    const double start = omp_get_wtime();
    auto cross_into = [&](std::size_t q, double& excess) BAGDEM_INLINE_LAMBDA {
      const std::uint32_t *cs = ps_.cross_into.data() + ps_.cross_into_range[q], *end = ps_.cross_into.data() + ps_.cross_into_range[q + 1];
      for (; cs < end; cs += kBlock) cross_block(cs, std::min<std::size_t>(kBlock, static_cast<std::size_t>(end - cs)), travel, excess);
    };
    run_items(cross_into, r, r + 1, f.excess);
    cross_done_[r].region.store(stamp, std::memory_order_release);
    balance_.add(r, omp_get_wtime() - start);
  };
  // false: given up waiting (give_up(); the range is left half done).
  auto range_part = [&](std::size_t r, double travel, const WallMotion& cavity, std::uint64_t stamp, StageFold& f,
                        const auto& give_up) BAGDEM_INLINE_LAMBDA {
    const double start = omp_get_wtime();
    auto head = [&](std::size_t q, StageFold& g) BAGDEM_INLINE_LAMBDA { range_head(q, travel, g); };
    run_items(head, r, r + 1, f);
    const double paused = omp_get_wtime();
    for (std::size_t c = r + 1; c <= ps_.records_upto[r]; ++c)
      if (!spin_until([&] { return cross_done_[c].region.load(std::memory_order_acquire) >= stamp; }, give_up)) return false;
    const double resumed = omp_get_wtime();
    auto tail = [&](std::size_t q, StageFold& g) BAGDEM_INLINE_LAMBDA { range_tail(q, travel, cavity, g); };
    run_items(tail, r, r + 1, f);
    balance_.add(r, (paused - start) + (omp_get_wtime() - resumed));  // its work, not its wait
    return true;
  };
  if (pipelined == 0) {
    StageFold fold;
    const std::uint64_t region = ++pair_regions_;
    const double travel = travel_;
    const WallMotion cavity = rigid_motion();
#pragma omp parallel
    {
      StageFold mine;
      const auto me = static_cast<std::size_t>(omp_get_thread_num()), team = static_cast<std::size_t>(omp_get_num_threads());
      for (std::size_t r = me; r < ranges; r += team) cross_part(r, travel, region, mine);
      for (std::size_t r = me; r < ranges; r += team) range_part(r, travel, cavity, region, mine, [] { return false; });
#pragma omp critical(bagdem_pair_excess)
      fold.merge(mine);
    }
    end_pair_stage(fold, drift != nullptr);
    return 0;
  }
  // Pipelined steps (run_pipelined): the threads stay in one region for up to `pipelined` steps
  // and meet nowhere. Range r goes on to step s once the ranges whose balls its cross pairs reach
  // are at step s (RangeProgress::done), and every range's rebuild decision for it is known (the
  // positions at step s - 1, Stepper::kSkinStep). A guard that fails ends the steps for all:
  // each goes on only up to that step (stop_before_), so the first failing step is found.
  const std::uint64_t base = pair_regions_;
  const std::size_t nr = ranges;
  RangeProgress* progress = progress_.data();
  auto at_least = [progress](std::size_t q0, std::size_t q1, std::uint64_t steps) {
    for (std::size_t q = q0; q < q1; ++q)
      if (progress[q].done.load(std::memory_order_acquire) < steps) return false;
    return true;
  };
#pragma omp parallel
  {
    const auto me = static_cast<std::size_t>(omp_get_thread_num()), team = static_cast<std::size_t>(omp_get_num_threads());
    for (std::uint64_t s = 0;; ++s) {
      auto give_up = [this, s] { return stop_before_.load(std::memory_order_acquire) <= s; };
      if (s >= 2 && !spin_until([&] { return at_least(0, nr, s - 1); }, give_up)) break;
      if (give_up()) break;
      bool going = true;
      for (std::size_t r = me; going && r < nr; r += team) {
        going = spin_until([&] { return at_least(ps_.cross_from[r], r, s); }, give_up);
        if (going) {
          progress[r].fold = StageFold{};
          progress[r].cross = cross_travel(r, s);
          cross_part(r, progress[r].cross, base + s + 1, progress[r].fold);
        }
      }
      for (std::size_t r = me; going && r < nr; r += team) {
        going = range_part(r, progress[r].travel[s % 4], wall_path_[s], base + s + 1, progress[r].fold, give_up);
        if (going) end_range_step(r, s);
      }
      if (!going) break;
    }
  }
  return progress[0].done.load(std::memory_order_relaxed);
}

}  // namespace bagdem
