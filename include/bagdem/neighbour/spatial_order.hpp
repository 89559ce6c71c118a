// The order the stepper keeps the balls in. Balls close in space get close indices, so contiguous
// index ranges are compact pieces of the bed: each thread of the pair stage sums one range, and only
// the pairs across a range boundary need records (PairState); the arrays a ball's neighbours touch
// also lie close in memory. LAMMPS and LIGGGHTS reorder their atoms for the same reasons
// (atom_modify sort).
//
// Slabs one largest ball diameter thick across the longest side of the balls' bounding box, then
// layers of the same thickness across the shortest side, then the coordinate along the third:
// cutting the order anywhere cuts the bed across its longest side, where the cut is smallest, and
// within a slab the balls that lie on one wall of a flat bed (its floor) come in runs, which the
// wall stage's branches predict. (Sorting the last two the other way round, columns of a few balls
// each, made one thread 15-20% slower on the PD-box bed at N = 10000, all of it in the wall stage.)
#pragma once
#include <cstdint>
#include <vector>

#include "bagdem/scene.hpp"

namespace bagdem {

// Below this many balls the stepper keeps the scene's order (everything runs on one thread there,
// kParallelMin, and the arrays fit in cache).
inline constexpr std::size_t kSpatialOrderMin = 512;

// The scene's balls in the stepper's order: element i is the scene index of the stepper's ball i.
// The bag's balls, [bag.ball_first, bag.ball_first + bag.balls), are sorted among themselves and
// keep their place, as do the balls before and after them. The order depends only on the balls'
// initial positions and radii (ties keep the scene's order).
std::vector<std::uint32_t> spatial_order(const Scene& scene);

}  // namespace bagdem
