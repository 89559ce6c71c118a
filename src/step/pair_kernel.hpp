// The pair kernel: the pairs stage's work on a span of candidate pairs (geometry -> contact law ->
// forces on the balls), a function of its views (the step's context, the scene, the balls, the
// pair contacts), with the arrays it reads held in locals for the stage (a store may alias any
// member of a component, and the compiler would load each array's address again after every
// store; the flag stores to `touching` alias anything). Which thread does which span, and when, is
// the schedule's (pair_schedule.cpp). Every piece is inlined into the schedule's loops.
#pragma once
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "bagdem/contact/hertz.hpp"
#include "bagdem/contact/surface_law.hpp"
#include "bagdem/scene.hpp"
#include "balls.hpp"
#include "history.hpp"
#include "pair_contacts.hpp"
#include "stage.hpp"

namespace bagdem {

// Pairs per block (block), and candidates per step of its scan for the awake.
constexpr std::size_t kBlock = 128, kScanWidth = 16;
// The kernel fetches the balls' state ahead (fetch_balls) from this many balls on (below, it stays
// in cache from step to step), when the pairs reach at most this far (a bed in the stepper's order:
// spatial_order).
constexpr std::size_t kFetchAheadMin = 16384, kFetchAheadMax = 4096;

// A pair contact opened this step: clears its history and returns what it still held
// (closing_tally, when Energy; else zero). Rare, so kept out of line: the pair loop stays small.
template <bool Tangential, bool Rolling, bool Energy>
[[gnu::noinline]] Vec3 open_pair(PairContacts& ps, const Balls& b, double dt, std::size_t k) {
  ps.touching[k] = 0;
  return ps.hist.open<Tangential, Rolling, Energy>(k, dt, [&] {
    const std::uint32_t i = ps.first[k], j = ps.pairs.partner[k];
    const Vec3 n = (b.x[i] - b.x[j]).normalized();
    return OpeningMotion{n, b.v[i] - b.v[j] - (b.radius[i] * b.w[i] + b.radius[j] * b.w[j]).cross(n), b.w[i] - b.w[j]};
  });
}

// Uniform: all balls alike, so their radius, inverse mass and law are the first ball's (the same
// values, so the same results; R* and m* are then loop constants, two divisions fewer per contact).
template <bool Tangential, bool Rolling, bool Energy, bool Uniform>
struct PairKernel {
  PairContacts& pairs_state;
  const Balls& balls;
  const double dt, frac;
  const PairLawTable* laws;
  const double r0, im0;
  const PairLaw* law0;
  const Vec3 *x, *v, *w, *v_pred, *w_pred;
  const double *radii, *inv_mass;
  const int* material;
  Vec3 *f, *t, *diss;
  const std::uint32_t *first, *partner;
  std::uint8_t* touching;
  double* damping_prev;
  TangentialHistory* tangential;
  RollingHistory* rolling;
  const std::uint32_t* cross;
  PairState::Record* rec;
  Vec3* rec_diss;
  float* wake;
  const std::uint8_t* is_cross;
  const std::size_t nballs, reach;
  const bool fetch_ahead;

  PairKernel(const StepContext& ctx, const Scene& scene, Balls& b, PairContacts& ps)
      : pairs_state(ps), balls(b), dt(ctx.dt), frac(scene.max_overlap_fraction), laws(&scene.laws),
        r0(ps.pairs.size() > 0 ? b.radius[0] : 0.0), im0(ps.pairs.size() > 0 ? b.inv_mass[0] : 0.0),
        law0(ps.pairs.size() > 0 ? &scene.laws(b.material[0], b.material[0]) : nullptr),
        x(b.x.data()), v(b.v.data()), w(b.w.data()), v_pred(b.v_pred.data()), w_pred(b.w_pred.data()),
        radii(b.radius.data()), inv_mass(b.inv_mass.data()), material(b.material.data()), f(b.f.data()),
        t(b.t.data()), diss(b.tally.step_dissipation.data()), first(ps.first.data()),
        partner(ps.pairs.partner.data()), touching(ps.touching.data()), damping_prev(ps.hist.damping_prev.data()),
        tangential(ps.hist.tangential.data()), rolling(ps.hist.rolling.data()), cross(ps.cross.data()),
        rec(ps.rec.data()), rec_diss(ps.rec_diss.data()), wake(ps.wake.data()), is_cross(ps.is_cross.data()),
        nballs(b.size()), reach(ps.reach), fetch_ahead(nballs >= kFetchAheadMin && reach <= kFetchAheadMax) {}

  BAGDEM_INLINE double radius(std::uint32_t i) const { return Uniform ? r0 : radii[i]; }

  // A pair's force, torques and dissipation as rows of 4 doubles (x, y, z, unused).
  struct alignas(32) Out {
    double F[4], Ti[4], Tj[4], diss[4];
  };
  static BAGDEM_INLINE Vec3 vec(const double* row) { return Vec3(row[0], row[1], row[2]); }

  // The contact law on kLanes pairs side by side (surface_contact_lanes): lane l is the pair ks[l]
  // for l < n; the lanes past n repeat the last pair (its histories are written again with the same
  // values, its results go to out[n..kLanes), unused). Each pair's results go to out[l], its
  // histories are updated. No accumulation here.
  BAGDEM_INLINE void lanes(const std::uint32_t* ks, int n, Out* out, double& excess) const {
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
    const double step = dt;
    auto with_law = [&](const auto& law) BAGDEM_INLINE_LAMBDA {
      const SurfaceLanes c = surface_contact_lanes<Tangential, Rolling, Energy>(g, law, step, damping, th, rh);
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
      with_law(e);
    }
  }

  // A closed pair's force, torques and dissipation onto its particles.
  BAGDEM_INLINE void apply(std::size_t k, const Out& o) const {
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
  }
  // The same into cross pair c's records (-F on j: f - F and f + (-F) are the same bits).
  BAGDEM_INLINE void record(std::size_t c, const Out& o) const {
    touching[cross[c]] = 1;
    const Vec3 F = vec(o.F);
    rec[2 * c] = {F, Tangential || Rolling ? vec(o.Ti) : Vec3::Zero()};
    rec[2 * c + 1] = {-F, Tangential || Rolling ? vec(o.Tj) : Vec3::Zero()};
    if constexpr (Energy) rec_diss[c] = vec(o.diss);
  }
  // Record e (of cross pair e / 2) onto particle p.
  BAGDEM_INLINE void add_record(std::uint32_t p, std::size_t e) const {
    f[p] += rec[e].force;
    if constexpr (Tangential || Rolling) t[p] += rec[e].torque;
    if constexpr (Energy) diss[p] += 0.5 * rec_diss[e / 2];
  }
  // Whether pair k touches now: the one test of contact (sphere_sphere's, spheres_apart), and when
  // it may touch at the earliest (PairState::wake): at once when it touches now or touched at the
  // last step (an opened pair's tallies and records are cleared at the next look), else once travel
  // has grown by half its gap, less 1e-9 of the radii's sum, which covers the rounding of the gap
  // (about 1e-16 of it) many times over. travel: the stepper's, or in pipelined steps the pair's
  // range's (pipelined_region).
  BAGDEM_INLINE bool look(std::uint32_t k, double travel) const {
    const std::uint32_t i = first[k], j = partner[k];
    const double rsum = radius(i) + radius(j);
    const bool now = !spheres_apart(x[i], x[j], rsum);
    const Vec3 d = x[i] - x[j];
    const double gap = std::sqrt(dot(d, d)) - rsum;
    wake[k] = round_down_to_float((now | (touching[k] != 0)) ? travel : travel + 0.5 * gap - 1e-9 * rsum);
    return now;
  }
  // Pair k may touch: its histories are fetched now, while the block's other pairs are looked at,
  // so that they are in cache when the law reads them. Closed pairs are a few in a hundred
  // candidates, so the hardware prefetchers do not follow their histories.
  BAGDEM_INLINE void fetch_histories(std::uint32_t k) const {
    if constexpr (Tangential) prefetch_object(&tangential[k], kTangentialBytes<Energy>);
    if constexpr (Rolling) prefetch_object(&rolling[k]);
  }
  // A pair opened: its closing tally onto its balls, its history cleared (open_pair).
  BAGDEM_INLINE void open(std::uint32_t k) const {
    const Vec3 d = open_pair<Tangential, Rolling, Energy>(pairs_state, balls, dt, k);
    if constexpr (Energy) {
      diss[first[k]] += 0.5 * d;
      diss[partner[k]] += 0.5 * d;
    }
  }

  // Pairs [k0, k1) of one block, in four passes:
  //  0. the pairs that may touch (awake: PairState::wake), and in a block that holds any (Cross)
  //     the cross pairs (computed already); in the shaken PD-box bed about a fifth of the candidates;
  //  1. among those, a branch-free scan for the pairs that touch now (`closed`), those that touched
  //     at the last step and are apart now (`opened`) and the cross pairs;
  //  2. the contact law on the closed pairs, kLanes at a time (lanes);
  //  3. in pair order: each closed pair applied, each opened pair closed, each cross pair's record
  //     added to its i. c0: the block's first cross pair.
  template <bool Cross>
  BAGDEM_INLINE void block(std::size_t k0, std::size_t k1, std::size_t c0, double travel, double& excess) const {
    std::uint32_t awake[kBlock + kScanWidth], closed[kBlock], opened[kBlock], crossing[Cross ? kBlock : 1];
    std::size_t na = 0, nc = 0, no = 0, nx = 0;
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
        const bool is = is_cross[k] != 0;
        crossing[nx] = k;
        nx += is;
        if (is) continue;
      }
      const bool now = look(k, travel);
      fetch_histories(now ? k : static_cast<std::uint32_t>(k0));  // without a branch: the block's first is at hand
      nc += now;
      no += !now & (touching[k] != 0);
    }
    Out out[kBlock + kLanes];  // the last lanes of a block may run past nc
    for (std::size_t a = 0; a < nc; a += kLanes) lanes(closed + a, static_cast<int>(std::min<std::size_t>(kLanes, nc - a)), out + a, excess);
    constexpr std::uint32_t kNone = ~0u;
    for (std::size_t a = 0, o = 0, c = 0; a < nc || o < no || c < nx;) {
      const std::uint32_t ka = a < nc ? closed[a] : kNone, ko = o < no ? opened[o] : kNone;
      const std::uint32_t kc = Cross && c < nx ? crossing[c] : kNone;
      if (ka < ko && ka < kc) {
        apply(ka, out[a++]);
      } else if (ko < kc) {
        open(ko);
        ++o;
      } else {
        add_record(first[kc], 2 * (c0 + c));  // the block's cross pairs are c0, c0 + 1, ...
        ++c;
      }
    }
  }

  // Cross pairs cs[0, n), n <= kBlock, into their records (zero when apart, the closing tally when
  // just opened).
  BAGDEM_INLINE void cross_block(const std::uint32_t* cs, std::size_t n, double travel, double& excess) const {
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
      const Vec3 d = touching[k] != 0 ? open_pair<Tangential, Rolling, Energy>(pairs_state, balls, dt, k) : Vec3::Zero();
      rec[2 * c] = rec[2 * c + 1] = {Vec3::Zero(), Vec3::Zero()};
      if constexpr (Energy) rec_diss[c] = d;
    }
    Out out[kBlock + kLanes];
    for (std::size_t a = 0; a < nc; a += kLanes) lanes(closed + a, static_cast<int>(std::min<std::size_t>(kLanes, nc - a)), out + a, excess);
    for (std::size_t a = 0; a < nc; ++a) record(at[a], out[a]);
  }

  // The balls' state ahead of the pairs: at ball i, the balls up to i + reach. In a bed sorted by
  // slabs (spatial_order) ball j is first reached from the slab before its own, about a slab's
  // worth of balls after its last use: far enough for the caches to have lost it, and reached
  // in an order the hardware prefetchers do not follow. Every second ball: a Vec3 is 24 bytes, so
  // each 64-byte line holds the start of one of them.
  BAGDEM_INLINE void fetch_balls(std::size_t& ahead, std::size_t upto) const {
    upto = std::min(upto, nballs);
    for (; ahead < upto; ahead += 2) {
      prefetch_object(&x[ahead]), prefetch_object(&v[ahead]), prefetch_object(&v_pred[ahead]), prefetch_object(&f[ahead]);
      if constexpr (Tangential || Rolling) prefetch_object(&w[ahead]), prefetch_object(&w_pred[ahead]), prefetch_object(&t[ahead]);
    }
  }
  // The histories of the pairs [from, to) that touched at the last step: most of them touch again
  // (a contact lasts many steps), so they are fetched a block ahead of their law.
  BAGDEM_INLINE void fetch_touching(std::size_t from, std::size_t to) const {
    std::size_t k = from;
#if defined(__AVX512BW__)
    for (; k + 64 <= to; k += 64)
      for (std::uint64_t m = _mm512_test_epi8_mask(_mm512_loadu_si512(touching + k), _mm512_set1_epi8(1)); m != 0; m &= m - 1)
        fetch_histories(static_cast<std::uint32_t>(k + static_cast<std::size_t>(std::countr_zero(m))));
#endif
    for (; k < to; ++k)
      if (touching[k] != 0) fetch_histories(static_cast<std::uint32_t>(k));
  }

  // Pairs [k0, k1) in blocks.
  BAGDEM_INLINE void span(std::size_t k0, std::size_t k1, double travel, double& excess) const {
    const std::vector<std::uint32_t>& crossing = pairs_state.cross;
    std::size_t ahead = k0 < k1 ? first[k0] + reach : 0;
    if constexpr (Tangential || Rolling) fetch_touching(k0, std::min(k1, k0 + kBlock));
    for (std::size_t k = k0; k < k1; k += kBlock) {
      const std::size_t end = std::min(k1, k + kBlock);
      if (fetch_ahead) fetch_balls(ahead, first[end - 1] + reach + 1);
      if constexpr (Tangential || Rolling) fetch_touching(end, std::min(k1, end + kBlock));
      // Most blocks hold no cross pair: they take the scan without the cross test.
      const std::size_t c0 = static_cast<std::size_t>(std::lower_bound(crossing.begin(), crossing.end(), k) - crossing.begin());
      if (c0 < crossing.size() && crossing[c0] < end) {
        block<true>(k, end, c0, travel, excess);
      } else {
        block<false>(k, end, c0, travel, excess);
      }
    }
  }
};

}  // namespace bagdem
