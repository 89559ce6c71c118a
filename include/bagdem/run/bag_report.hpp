// What a bag is like now: its packing fraction and outer dimensions (reported when the settle phase
// ends), and its state as a saved bag for reuse (io/bag_file.hpp).
#pragma once
#include "bagdem/io/bag_file.hpp"
#include "bagdem/scene.hpp"
#include "bagdem/step/simulation.hpp"

namespace bagdem {

struct BagReport {
  double packing_fraction = 0;  // ball volume / volume inside the film (mid-surface volume less half the film)
  Vec3 outer = Vec3::Zero();    // outer extent along the bag's axis, side and height, film included (unit: m)
  Vec3 centre = Vec3::Zero();   // centroid of the balls (unit: m)
  double inner_volume = 0;      // (unit: m^3)
};

BagReport measure_bag(const Scene& scene, const Simulation& sim);
// The bag now, in the cavity frame, as bag.from reads it.
SavedBag saved_bag(const Scene& scene, const Simulation& sim);

}  // namespace bagdem
