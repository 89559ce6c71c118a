// The resolved bag of a scene ([bag] in case.toml, src/case/bag.cpp): the film's rest shape and
// initial node positions, its membrane properties and contact parameters, the strings that hold it,
// and which of the scene's particles are its balls. docs/reference-study.md, section 6.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "bagdem/bag/membrane.hpp"
#include "bagdem/mesh/triangle_mesh.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

// A tension-only elastic string from a tie on the bag to an anchor point on the cavity
// (src/bag/strings.cpp). Its load is shared equally by the tie's film nodes.
struct BagString {
  std::string name;                  // for messages ("bag.strings.0")
  std::vector<std::uint32_t> nodes;  // film nodes of the tie
  Vec3 anchor = Vec3::Zero();        // in the cavity frame (unit: m)
  double stiffness = 0;              // (unit: N/m)
  double damping = 0;                // acts only while taut (unit: N s/m)
  double rest_length = 0;            // (unit: m)
};

struct Bag {
  TriangleMesh rest;            // the film at rest (stress-free shape), topology built
  std::vector<Vec3> x0;         // node positions at t = 0: the rest shape, or a saved settled bag (unit: m)
  MembraneProperties film;      // membrane properties (damping_time resolved from damping_ratio)
  int material = 0;             // the film's material: its contact laws against balls and walls
  double contact_radius = 0;    // radius of a film node's contact with the cavity walls (unit: m)
  double damping_ratio = 0;     // membrane damping ratio at its highest frequency (for reports)
  double mass_scaling = 1;      // film node masses x this (a fidelity knob; 1 = physical)
  double max_frequency = 0;     // highest angular frequency of the membrane at rest (unit: rad/s)
  double bending_frequency = 0; // highest angular frequency of its bending alone at rest (unit: rad/s)
  // Bending on a slower clock (impulse multiple time stepping: Tuckerman, Berne & Martyna, J. Chem.
  // Phys. 97, 1992; Grubmueller et al., Mol. Sim. 6, 1991): the hinges' forces, N times over, at
  // every N-th step's positions, none between. The film's bending is far slower than the step
  // (omega_b dt ~ 1e-3 on the shipped bags): bag.film.bending_interval, resolve_bending_clock.
  int bending_interval = 1;
  double min_node_mass = 0;     // lightest film node, scaling included (unit: kg)
  double mean_edge = 0;         // mean edge length of the film at rest (unit: m)
  // Film-film contact (bag.film.self_contact): each node a sphere of this radius against the
  // film's nodes that are not its neighbours along an edge; 0: the film may pass through itself (unit: m).
  double self_radius = 0;

  std::string shape;            // "capsule" or "pillow"
  Vec3 axis = Vec3::UnitX();    // the bag's long axis, unit
  Vec3 side = Vec3::UnitY();    // its width direction, unit (height = axis x side)
  Vec3 size = Vec3::Zero();     // outer length, width, height at rest (unit: m)
  double fill_fraction = 0;     // ball volume / bag volume at rest
  double shrink = 1;            // bag.film.shrink: the film's unstretched size over the size it is made at
  std::string source;           // "filled on an FCC lattice (seed 1)" or "from <file>"

  // The film's physical mass: its area at rest x thickness x density (the node masses add up to
  // it, before mass_scaling) (unit: kg).
  double film_mass() const { return surface_area(rest, rest.vertices) * film.thickness * film.density; }

  std::size_t ball_first = 0;   // the bag's balls are Scene::particles[ball_first, ball_first + balls)
  std::size_t balls = 0;
  std::vector<BagString> strings;
};

}  // namespace bagdem
