// The damping calibration against its own definition and against the published overshoot of the
// clamped Tsuji law (docs/reference-study.md, section 4: asking 0.1/0.3/0.5/0.7/0.9 gives ~0.25/0.40/0.55/0.72/0.90).
#include <gtest/gtest.h>

#include <cmath>

#include "bagdem/contact/restitution.hpp"

using namespace bagdem;

TEST(RestitutionCalibration, UnclampedTsujiReturnsRequestedE) {
  for (double e : {0.05, 0.3, 0.5, 0.8, 0.95}) {
    const double a = std::sqrt(5.0) * (-tsuji_beta(e));
    EXPECT_NEAR(restitution_of_damping(a, false), e, 1e-5) << "e=" << e;
  }
}

TEST(RestitutionCalibration, ClampedTsujiOvershootsAsPublished) {
  const double requested[] = {0.1, 0.3, 0.5, 0.7, 0.9};
  const double published[] = {0.25, 0.40, 0.55, 0.72, 0.90};
  for (int k = 0; k < 5; ++k) {
    const double a = std::sqrt(5.0) * (-tsuji_beta(requested[k]));
    EXPECT_NEAR(restitution_of_damping(a, true), published[k], 0.01) << "e=" << requested[k];
  }
}

TEST(RestitutionCalibration, ClampedBetaInvertsTheClampedLaw) {
  for (double e : {0.01, 0.1, 0.5, 0.9, 0.99}) {
    const double a = std::sqrt(5.0) * clamped_beta(e);
    EXPECT_NEAR(restitution_of_damping(a, true), e, 1e-6 * std::max(1.0, e)) << "e=" << e;
  }
  EXPECT_EQ(clamped_beta(1.0), 0.0);
}
