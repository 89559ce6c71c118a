// A contact of a ball or a film node with a triangulated surface (the film, an STL wall), as the
// triangles stage keeps it from step to step (surfaces.cpp), and what a ball's film contact puts
// on the film's nodes.
#pragma once
#include <cstdint>

#include "bagdem/vec3.hpp"

namespace bagdem {

// One ball's (or film node's) contact with a feature of a triangulated surface (film or STL wall);
// its histories are in the slot's place of the stepper's ContactHistories (slot_hist_, node_slot_hist_).
struct MeshSlot {
  std::uint32_t surface = 0;          // 0 = the film when there is a bag, then the STL walls
  std::uint32_t key = 0;              // feature_key of the feature touched
  Vec3 n = Vec3::Zero();              // contact normal at the last step (towards the ball)
  Vec3 surface_velocity = Vec3::Zero();  // half-step velocity of the surface point (unit: m/s)
  double overlap = 0;                 // at the last step (unit: m)
};
// What a ball's film contact puts on the film's nodes: -force split by the barycentric weights.
struct FilmLoad {
  Vec3 force = Vec3::Zero();          // force on the film at the contact point (unit: N)
  Vec3 weights = Vec3::Zero();
  std::uint32_t triangle = 0;
};

}  // namespace bagdem
