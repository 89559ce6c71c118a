// The clearance of the contents in their cavity, measured on a live simulation: the gaps to the
// walls along the excitation direction (ReductionContext::clearance, the drop test's launch side).
#pragma once
#include "bagdem/scene.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

class Simulation;

// Gaps between the contents and the cavity's walls along +e and -e: the distances from the contents'
// centre of mass to the walls along the line through it (planes and bores; NaN with triangulated
// walls) less the contents' extent on that side (balls with their radius, film nodes).
struct ContentsGaps {
  double plus = 0, minus = 0;  // (m)
};
ContentsGaps contents_gaps(const Scene& scene, const Simulation& sim, const Vec3& e);
// Free travel d of the contents along e: the sum of the two gaps.
double contents_clearance(const Scene& scene, const Simulation& sim, const Vec3& e);

}  // namespace bagdem
