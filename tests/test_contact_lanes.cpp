// The contact law in lanes (lanes.hpp, surface_contact_lanes) against the same law on one contact
// (surface_contact): for random contacts, 4 side by side, every output and every history must be
// the same bits (both round each operation as written). The draws cover new contacts (zero
// history), sticking and sliding ones (history force 0.01 to 100 mu F_n), stiffness rising and
// falling, normal forces clamped to zero (with a zero friction cap and trial force: 0/0 in the
// cap's factor), lanes of different materials and of different laws (Hertz-Mindlin and Hooke side
// by side: each law run on all lanes, each lane keeping its own), and each configuration of the
// roles (tangential, rolling, energy). Also the lane loads and stores (gather3, gather4, to_rows) against
// element-wise copies.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <cstdio>
#include <algorithm>

#include "bagdem/contact/lanes.hpp"
#include "bagdem/contact/restitution.hpp"
#include "bagdem/contact/surface_law.hpp"
#include "bagdem/float_rounding.hpp"
#include "rng.hpp"

using namespace bagdem;
using bagdem::testing::Rng;

namespace {

// Hertz-Mindlin, or (2 draws in 5) the linear spring-dashpot (hooke.hpp).
PairLaw random_law(Rng& rng) {
  PairLaw law;
  if (rng.uniform() < 0.4) {
    law.kind = LawKind::Hooke;
    law.stiffness = std::pow(10.0, rng.uniform(2, 8));
    law.damping = 2 * rng.uniform(0.0, 0.95);
    law.tangential_ratio = std::sqrt(rng.uniform(0.2, 1.0));
    law.friction = rng.uniform(0.0, 0.8);
    law.rolling = rng.uniform(0.0, 0.1);
    return law;
  }
  law.E_star = rng.uniform(1e6, 2e11);
  law.G_star = law.E_star * rng.uniform(0.3, 0.5);
  law.damping = 2 * std::sqrt(5.0 / 6.0) * rng.uniform(0.0, 1.5);
  law.tangential_ratio = std::sqrt(4 * law.G_star / law.E_star);
  law.friction = rng.uniform(0.0, 0.8);
  law.rolling = rng.uniform(0.0, 0.1);
  return law;
}

struct Contact {
  ContactGeometry g;
  TangentialHistory th;
  RollingHistory rh;
  double damping_prev = 0;
};

Contact random_contact(Rng& rng) {
  Contact c;
  ContactGeometry& g = c.g;
  const double r = rng.uniform(0.5e-3, 5e-3);
  g.n = rng.unit();
  g.overlap = r * std::pow(10.0, rng.uniform(-6, -2));
  g.R_eff = rng.uniform(0.5, 1.0) * r;
  g.m_eff = rng.uniform(1e-6, 1e-2);
  g.arm_i = r - 0.5 * g.overlap;
  g.arm_j = rng.uniform() < 0.5 ? 0.0 : r - 0.5 * g.overlap;
  const double speed = std::pow(10.0, rng.uniform(-4, 0));
  g.v_rel = speed * draw_vec3([&] { return rng.normal(); });
  g.v_half = g.v_rel + 0.01 * speed * draw_vec3([&] { return rng.normal(); });
  g.w_half = 100 * speed * draw_vec3([&] { return rng.normal(); });
  if (rng.uniform() < 0.1) {
    // A new contact separating along its normal: F_n clamps to 0, so the friction cap is 0 and the
    // trial tangential force too (0/0 in the cap's factor, which must leave it at 1).
    g.v_rel = g.v_half = 10.0 * g.n;
    g.w_half = Vec3::Zero();
    return c;
  }
  if (rng.uniform() < 0.8) {  // an old contact; else a new one (zero history)
    const double F_n = 2e10 * std::sqrt(g.R_eff * g.overlap) * g.overlap;  // of the order of the normal force
    c.th.stiffness = 1e5 * std::pow(10.0, rng.uniform(-2, 2));
    c.th.force = F_n * std::pow(10.0, rng.uniform(-2, 2)) * rng.unit();
    c.th.force -= c.th.force.dot(g.n) * g.n * rng.uniform(0.0, 1.0);  // partly out of the plane: the normal turned
    c.th.total = c.th.force * rng.uniform(0.5, 1.5);
    c.rh.stiffness = 1e-3 * std::pow(10.0, rng.uniform(-2, 2));
    c.rh.torque = 1e-3 * F_n * std::pow(10.0, rng.uniform(-2, 2)) * rng.unit();
    c.damping_prev = rng.normal() * F_n;
  }
  return c;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
::testing::AssertionResult same_bits(const Vec3& a, const Vec3& b) {
  for (int d = 0; d < 3; ++d)
    if (!same_bits(a[d], b[d]))
      return ::testing::AssertionFailure() << "component " << d << ": " << a[d] << " vs " << b[d] << " (differ by "
                                           << a[d] - b[d] << ")";
  return ::testing::AssertionSuccess();
}

template <bool Tangential, bool Rolling, bool Energy>
void check_lanes_match_scalar(std::uint64_t seed) {
  Rng rng(seed);
  const double dt = 2e-7;
  for (int trial = 0; trial < 500; ++trial) {
    PairLaw laws[kLanes];
    const bool mixed = trial % 2 == 1;  // lanes of different materials, or one law for all
    for (int l = 0; l < kLanes; ++l) laws[l] = mixed || l == 0 ? random_law(rng) : laws[0];
    Contact c[kLanes];
    for (Contact& x : c) x = random_contact(rng);

    // One at a time.
    Contact scalar[kLanes];
    Vec3 F[kLanes], T[kLanes], diss[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      scalar[l] = c[l];
      T[l] = diss[l] = Vec3::Zero();
      F[l] = surface_contact<Tangential, Rolling, Energy>(scalar[l].g, laws[l], dt, scalar[l].damping_prev,
                                                          &scalar[l].th, &scalar[l].rh, T[l], diss[l]);
    }

    // Side by side.
    auto lanes = [&c](double (*of)(const ContactGeometry&)) {
      return Lanes{of(c[0].g), of(c[1].g), of(c[2].g), of(c[3].g)};
    };
    auto lanes3 = [&c](Vec3 ContactGeometry::*m) {
      return Lanes3{Lanes{(c[0].g.*m).x(), (c[1].g.*m).x(), (c[2].g.*m).x(), (c[3].g.*m).x()},
                    Lanes{(c[0].g.*m).y(), (c[1].g.*m).y(), (c[2].g.*m).y(), (c[3].g.*m).y()},
                    Lanes{(c[0].g.*m).z(), (c[1].g.*m).z(), (c[2].g.*m).z(), (c[3].g.*m).z()}};
    };
    ContactGeometryT<Lanes> g{lanes3(&ContactGeometry::n),
                              lanes([](const ContactGeometry& s) { return s.overlap; }),
                              lanes([](const ContactGeometry& s) { return s.R_eff; }),
                              lanes([](const ContactGeometry& s) { return s.m_eff; }),
                              lanes([](const ContactGeometry& s) { return s.arm_i; }),
                              lanes([](const ContactGeometry& s) { return s.arm_j; }),
                              lanes3(&ContactGeometry::v_rel),
                              lanes3(&ContactGeometry::v_half),
                              lanes3(&ContactGeometry::w_half)};
    double* damping[kLanes];
    TangentialHistory* th[kLanes];
    RollingHistory* rh[kLanes];
    for (int l = 0; l < kLanes; ++l) damping[l] = &c[l].damping_prev, th[l] = &c[l].th, rh[l] = &c[l].rh;
    const PairLaw* law_of[kLanes] = {&laws[0], &laws[1], &laws[2], &laws[3]};
    const SurfaceLanes out = mixed ? surface_contact_lanes<Tangential, Rolling, Energy>(g, law_of, dt, damping, th, rh)
                                   : surface_contact_lanes<Tangential, Rolling, Energy>(g, laws[0], dt, damping, th, rh);

    for (int l = 0; l < kLanes; ++l) {
      SCOPED_TRACE(::testing::Message() << "trial " << trial << ", lane " << l);
      EXPECT_TRUE(same_bits(lane(out.F, l), F[l]));
      // surface_contact's torque: -arm_i (n x F_t), then + the rolling torque.
      Vec3 torque = Vec3::Zero();
      if (Tangential) torque -= c[l].g.arm_i * lane(out.nxFt, l);
      if (Rolling) torque += lane(out.roll, l);
      EXPECT_TRUE(same_bits(torque, T[l]));
      if (Energy) {
        EXPECT_TRUE(same_bits(Vec3(Vec3::Zero() + lane(out.diss, l)), diss[l]));  // as added to a tally (-0 + 0 = 0)
        EXPECT_TRUE(same_bits(c[l].damping_prev, scalar[l].damping_prev));
      }
      if (Tangential) {
        EXPECT_TRUE(same_bits(c[l].th.force, scalar[l].th.force));
        EXPECT_TRUE(same_bits(c[l].th.stiffness, scalar[l].th.stiffness));
        if (Energy) {
          EXPECT_TRUE(same_bits(c[l].th.total, scalar[l].th.total));
        }
      }
      if (Rolling) {
        EXPECT_TRUE(same_bits(c[l].rh.torque, scalar[l].rh.torque));
        EXPECT_TRUE(same_bits(c[l].rh.stiffness, scalar[l].rh.stiffness));
      }
    }
    if (::testing::Test::HasFailure()) return;
  }
}

}  // namespace

TEST(ContactLanes, LanesGiveTheScalarLawsBits) {
  check_lanes_match_scalar<true, false, false>(1);  // the PD-box's law
  check_lanes_match_scalar<true, true, false>(2);
  check_lanes_match_scalar<true, true, true>(3);
  check_lanes_match_scalar<false, false, true>(4);
  check_lanes_match_scalar<false, true, false>(5);
}

TEST(ContactLanes, LoadsAndStoresMoveEachValueToItsLane) {
  Rng rng(7);
  std::vector<Vec3> v(9);
  for (Vec3& x : v) x = draw_vec3([&] { return rng.normal(); });
  const std::uint32_t at[kLanes] = {8, 0, 3, 3};  // the last element too (a load must not read past it)
  const Lanes3 g = gather3(v.data(), at);
  double rows[kLanes][5];
  const double* from[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    EXPECT_TRUE(same_bits(lane(g, l), v[at[l]]));
    for (int c = 0; c < 5; ++c) rows[l][c] = rng.normal();
    from[l] = rows[l];
  }
  Lanes3 v4;
  Lanes w4;
  gather4(from, v4, w4);
  double back[kLanes][5] = {};
  double* to[kLanes] = {back[0], back[1], back[2], back[3]};
  to_rows(v4, w4, to);
  for (int l = 0; l < kLanes; ++l) {
    EXPECT_TRUE(same_bits(lane(v4, l), Vec3(rows[l][0], rows[l][1], rows[l][2])));
    EXPECT_TRUE(same_bits(w4[l], rows[l][3]));
    for (int c = 0; c < 4; ++c) EXPECT_TRUE(same_bits(back[l][c], rows[l][c]));
    EXPECT_EQ(back[l][4], 0.0);  // a row is 4 doubles: nothing written after it
  }
}

// round_down_to_float (the pair stage's wake bounds): the largest float not above the double, for
// doubles of every size the bounds take (1e-12 to 10 m), their negatives, zero, floats exactly,
// and NaN. Against the definition: f <= v < the next float up.
TEST(ContactLanes, RoundDownToFloatIsTheLargestFloatNotAbove) {
  Rng rng(11);
  std::vector<double> values = {0.0, 1.0, -1.0, 0.1, -0.1, 1e-4, 3.0 / 7.0, static_cast<double>(0.1f)};
  for (int i = 0; i < 20000; ++i) {
    const double v = std::pow(10.0, rng.uniform(-12, 1));
    values.push_back(i % 4 == 3 ? -v : v);
  }
  int rounded = 0;
  for (const double v : values) {
    const float f = round_down_to_float(v);
    ASSERT_LE(static_cast<double>(f), v) << v;
    ASSERT_GT(static_cast<double>(std::nextafter(f, HUGE_VALF)), v) << v;
    rounded += static_cast<double>(f) != v;
  }
  EXPECT_GT(rounded, 19000);  // nearly every draw needs rounding: the test sees both directions of it
  EXPECT_TRUE(std::isnan(round_down_to_float(std::nan(""))));
}

// atan2_unit (lanes.hpp), the film hinges' angle, against libm's atan2 on |s| <= c: relative error
// within 6e-16 (about 3 ulp) at 200 001 ratios and on both sides of the reduction's switch at
// tan(pi/8), for two scales of c; odd in s; and each lane gives the scalar's bits.
TEST(ContactLanes, Atan2UnitMatchesLibm) {
  double worst = 0;
  auto check = [&](double s, double c) {
    const double ref = std::atan2(s, c), got = atan2_unit(s, c);
    if (ref != 0) worst = std::max(worst, std::abs(got - ref) / std::abs(ref));
    EXPECT_EQ(atan2_unit(-s, c), -got) << s << " " << c;
    const Lanes l = atan2_unit(Lanes{s, -s, 0.5 * s, s}, Lanes{c, c, c, 2 * c});
    EXPECT_EQ(l[0], got);
    EXPECT_EQ(l[1], atan2_unit(-s, c));
    EXPECT_EQ(l[2], atan2_unit(0.5 * s, c));
    EXPECT_EQ(l[3], atan2_unit(s, 2 * c));
  };
  for (double c : {1.0, 3.7e-9})
    for (int i = -100000; i <= 100000; ++i) check(i * 1e-5 * c, c);
  const double t = std::tan(std::numbers::pi / 8);
  for (int k = -50; k <= 50; ++k) check(t + k * 1e-17, 1.0);
  std::printf("  atan2_unit: largest relative error %.3e\n", worst);
  EXPECT_LE(worst, 6e-16);
  EXPECT_EQ(atan2_unit(0.0, 1.0), 0.0);
  EXPECT_NEAR(atan2_unit(1.0, 1.0), std::numbers::pi / 4, 2e-16);
}
