// A bag pulled tight around its balls (bag.film.shrink, docs/bag.md "Tight bags"). Internal to
// src/case (bag.cpp).
#pragma once
#include "bagdem/bag/bag.hpp"
#include "bagdem/case/case_reader.hpp"

namespace bagdem {

// bag.film.shrink s < 1: the film is made where the lattice holds the balls (b.rest as made), but
// its unstretched size is s times that (each length, about its centroid), so it starts stretched
// by 1/s and closes on the balls while they settle, packing them closer than the lattice can; the
// fill fraction is then the unstretched film's. Sets b.shrink and scales b.rest; refuses (InputError)
// a value out of [0.7, 1] or one whose unstretched film would hold the balls (of total volume
// `ball_volume`, m^3) above random close packing.
void pull_tight(const CaseReader& in, double ball_volume, Bag& b);

}  // namespace bagdem
