// The energy budget of the contents, as the stepper tallies it (Stepper::energy).
#pragma once
#include <array>

namespace bagdem {

// One row of the energy budget (unit: J). Balance: work_cavity + work_gravity =
// (kinetic + elastic) - (kinetic + elastic at t = 0) + dissipated_normal + dissipated_tangential
// + dissipated_rolling + dissipated_damping (= dissipated()).
struct EnergySample {
  double kinetic = 0;               // translational + rotational
  double elastic = 0;               // stored in contact springs (normal, tangential, rolling)
  double work_cavity = 0;           // cumulative work of the cavity walls on the contents
  double work_gravity = 0;          // cumulative work of gravity on the contents
  double dissipated_normal = 0;     // cumulative, normal damping
  double dissipated_tangential = 0; // cumulative, tangential damping and sliding
  double dissipated_rolling = 0;    // cumulative, rolling resistance
  double dissipated_damping = 0;    // cumulative, the bag's film damping and its strings' dampers
  double dissipated() const { return dissipated_normal + dissipated_tangential + dissipated_rolling + dissipated_damping; }
  // The terms in the order of results.h5's /energy datasets (io/results_file.hpp, kEnergyTerms).
  std::array<double, 8> terms() const {
    return {kinetic, elastic, work_cavity, work_gravity, dissipated_normal, dissipated_tangential, dissipated_rolling,
            dissipated_damping};
  }
};

}  // namespace bagdem
