// The table the contact kernel reads per pair of materials, built from the materials and the
// interaction of each pair: effective moduli (material.hpp) and the damping factor of the
// requested restitution (contact/restitution.hpp).
#pragma once
#include <vector>

#include "bagdem/material.hpp"

namespace bagdem {

// Builds the table from materials and the interaction of each pair (interactions[a*n+b]).
PairLawTable make_pair_laws(const std::vector<Material>& materials,
                            const std::vector<Interaction>& interactions);

}  // namespace bagdem
