// The smooth start of a prescribed motion (src/motion/ramp.cpp): x_r = x0 + s (x - x0),
// v_r = s' (x - x0) + s v with x0 = x(0), s = (1 - cos(pi t/T_r))/2 on [0, T_r], s = 1 after; and the
// case key cavity.motion.ramp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/motion/motion.hpp"
#include "case_texts.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::TempDir;

namespace {

// A harmonic motion with a phase, so that the unramped motion starts with both a position and a
// velocity jump (X sin(phase), X w cos(phase)) and the ramp has something to remove.
constexpr double kX = 1e-3, kF = 30, kPhase = 0.7, kTr = 0.05;  // m, Hz, rad, s (1.5 periods)
const double kW = 2 * std::numbers::pi * kF;
const Vec3 kDir = Vec3(1, 2, 2) / 3;

std::unique_ptr<Motion> ramped_harmonic(double phase = kPhase, double ramp = kTr) {
  return make_ramped_motion(make_harmonic_motion(kX, kF, kDir, phase), ramp);
}

// The analytic ramped motion, written out independently of the implementation.
CavityState analytic(double t, double phase = kPhase, double ramp = kTr) {
  const double s = t < ramp ? (1 - std::cos(std::numbers::pi * t / ramp)) / 2 : 1.0;
  const double ds = t < ramp ? std::numbers::pi / (2 * ramp) * std::sin(std::numbers::pi * t / ramp) : 0.0;
  const double x0 = kX * std::sin(phase);
  const double x = kX * std::sin(kW * t + phase), v = kX * kW * std::cos(kW * t + phase);
  return {(x0 + s * (x - x0)) * kDir, (ds * (x - x0) + s * v) * kDir};
}

}  // namespace

TEST(MotionRamp, MatchesTheAnalyticFormulaInsideAndAfterTheRamp) {
  // Relative 1e-12 of the motion's scales: X for the position, X w for the velocity.
  const auto m = ramped_harmonic();
  for (double t : {1e-4, 0.003, 0.0123, 0.025, 0.0371, 0.0499, 0.05, 0.0613, 0.2, 1.234}) {
    const CavityState got = m->at(t), want = analytic(t);
    EXPECT_LE((got.position - want.position).norm(), 1e-12 * kX) << "t = " << t;
    EXPECT_LE((got.velocity - want.velocity).norm(), 1e-12 * kX * kW) << "t = " << t;
  }
  // Inside the ramp the motion really is reduced (not the inner motion unchanged).
  const auto inner = make_harmonic_motion(kX, kF, kDir, kPhase);
  EXPECT_GT((m->at(0.0123).position - inner->at(0.0123).position).norm(), 1e-2 * kX);
  // After the ramp it is the inner motion exactly.
  EXPECT_EQ(m->at(0.2).position, inner->at(0.2).position);
  EXPECT_EQ(m->at(0.2).velocity, inner->at(0.2).velocity);
}

TEST(MotionRamp, StartsAtRestAndJoinsTheInnerMotionContinuously) {
  const auto m = ramped_harmonic();
  // t = 0: s = s' = 0 exactly, so the cavity is where it settled (x0 = X sin(0.7)) and at rest,
  // although the inner motion starts with velocity X w cos(0.7).
  const Vec3 x0 = kX * std::sin(kPhase) * kDir;
  EXPECT_EQ(m->at(0.0).position, x0);
  EXPECT_EQ(m->at(0.0).velocity.norm(), 0.0);
  // Just after 0: displacement O(t^2) (s ~ (pi t/T_r)^2/4), velocity O(t). With e = 1e-9 s the
  // displacement is ~1e-12 X and the velocity ~2e-8 X/T_r; an impulsive start would move at X w.
  const double e = 1e-9;
  EXPECT_LE((m->at(e).position - x0).norm(), 1e-12 * kX);
  EXPECT_LE(m->at(e).velocity.norm(), 1e-6 * kX * kW);
  // t = T_r: from both sides within e, position and velocity differ by at most e times the
  // largest velocity / acceleration (< 2 X w and < 4 X w^2 here), i.e. ~1e-6 X, ~1e-6 X w.
  // A ramp that is only C0 (e.g. linear) would have a velocity jump x(T_r)/T_r ~ 0.1 X w.
  const CavityState a = m->at(kTr - e), b = m->at(kTr), c = m->at(kTr + e);
  EXPECT_LE((a.position - b.position).norm(), 1e-5 * kX);
  EXPECT_LE((c.position - b.position).norm(), 1e-5 * kX);
  EXPECT_LE((a.velocity - b.velocity).norm(), 1e-5 * kX * kW);
  EXPECT_LE((c.velocity - b.velocity).norm(), 1e-5 * kX * kW);
}

TEST(MotionRamp, VelocityIsTheDerivativeOfThePosition) {
  // Central difference with h = 1e-6 s: truncation h^2/6 |x'''| with |x'''| < (w + pi/T_r)^3 X
  // ~ 1.6e7 X/s^3 gives < 3e-6 X/s = 2e-8 X w; rounding eps X/h ~ 2e-13 m/s ~ 1e-12 X w. Tolerance
  // 1e-6 X w. Points stay farther than h from t = T_r, where the acceleration jumps (s'' does).
  // Dropping the s' x term would be off by up to pi/(2 T_r) X ~ 0.17 X w.
  const auto m = ramped_harmonic();
  const double h = 1e-6;
  for (double t = 0.0004; t < 3 * kTr; t += 0.00137) {
    ASSERT_GT(std::abs(t - kTr), 2 * h);
    const Vec3 d = (m->at(t + h).position - m->at(t - h).position) / (2 * h);
    EXPECT_LE((d - m->at(t).velocity).norm(), 1e-6 * kX * kW) << "t = " << t;
  }
}

TEST(MotionRamp, MaxSpeedBoundsTheRampedSpeedAndFrequencyForwards) {
  // The bound must hold against 40001 samples over the ramp and one period after it, and not be
  // loose by more than a factor 2 (it adds the inner peak speed and the ramp term), for short and long ramps, starting at a node (phase 0) and at a crest
  // (phase pi/2) of the motion.
  for (double phase : {0.0, std::numbers::pi / 2})
    for (double ramp : {0.05 / kF, kTr}) {
      const auto m = ramped_harmonic(phase, ramp);
      const double span = ramp + 1 / kF;
      double vmax = 0;
      for (int i = 0; i <= 40000; ++i) vmax = std::max(vmax, m->at(span * i / 40000.0).velocity.norm());
      EXPECT_GE(m->max_speed(), vmax) << "ramp = " << ramp << ", phase = " << phase;
      EXPECT_LE(m->max_speed(), 2.0 * vmax) << "ramp = " << ramp << ", phase = " << phase;
      EXPECT_DOUBLE_EQ(m->frequency(), kF);
      EXPECT_DOUBLE_EQ(m->ramp_time(), ramp);
    }
  EXPECT_THROW(make_ramped_motion(make_fixed_motion(), 0.0), std::invalid_argument);
}

namespace {
struct CaseDir : TempDir {
  explicit CaseDir(const std::string& toml) { write("case.toml", toml); }
};

// 5 steel balls in a 21 x 21 x 48 mm box, no gravity, the box moving 1 mm at 30 Hz along (1, 2, 2)
// from phase 0.7; `motion` are more [cavity.motion] keys.
std::string harmonic_case(const bagdem::testing::CaseText::Keys& motion) {
  return bagdem::testing::steel_scene("1 ms")
      .erase("simulation", "gravity")
      .box("steel", "[0, 0, 0]", bagdem::testing::vec("21 mm", "21 mm", "48 mm"))
      .harmonic("1 mm", "30 Hz", "[1, 2, 2]")
      .set("cavity.motion", "phase", 0.7)
      .set("cavity.motion", motion)
      .balls("balls", "steel", "4 mm", 5);
}
}  // namespace

TEST(MotionRamp, CaseKeyAppliesTheRamp) {
  CaseDir c(harmonic_case({{"ramp", "50 ms"}}));
  const Scene s = load_case(c.str());
  for (double t : {0.0, 0.004, 0.021, 0.049, 0.05, 0.08}) {
    const CavityState got = s.motion->at(t), want = analytic(t);
    EXPECT_LE((got.position - want.position).norm(), 1e-12 * kX) << "t = " << t;
    EXPECT_LE((got.velocity - want.velocity).norm(), 1e-12 * kX * kW) << "t = " << t;
  }
  EXPECT_NE(s.motion->describe().find(", ramped in over 0.05 s"), std::string::npos) << s.motion->describe();
  EXPECT_DOUBLE_EQ(s.motion->frequency(), kF);
  // Without the key (or with 0) the motion starts at once: at t = 0 it is at X sin(0.7), speed X w cos(0.7).
  for (const char* extra : {"", "0"}) {  // no ramp key; ramp = 0
    CaseDir plain(harmonic_case(*extra ? bagdem::testing::CaseText::Keys{{"ramp", extra}} : bagdem::testing::CaseText::Keys{}));
    const Scene p = load_case(plain.str());
    EXPECT_NEAR(p.motion->at(0.0).velocity.norm(), kX * kW * std::cos(kPhase), 1e-12 * kX * kW) << extra;
    EXPECT_EQ(p.motion->describe().find("ramped"), std::string::npos) << extra;
  }
}

TEST(MotionRamp, NegativeRampIsRefused) {
  CaseDir c(harmonic_case({{"ramp", "-5 ms"}}));
  try {
    load_case(c.str());
    FAIL() << "a negative ramp was accepted";
  } catch (const InputError& e) {
    // Refused by the ramp check itself, not as an unknown key.
    const std::string m = e.what();
    EXPECT_NE(m.find("cavity.motion.ramp"), std::string::npos) << m;
    EXPECT_NE(m.find("must be >= 0"), std::string::npos) << m;
  }
  // The same through --set.
  CaseDir ok(harmonic_case({}));
  EXPECT_THROW(load_case(ok.str(), {"cavity.motion.ramp=-0.01"}), InputError);
}
