// A contact of a ball or a film node with a triangulated surface (the film, an STL wall), as the
// triangles stage keeps it from step to step (surfaces.cpp), and what a ball's film contact puts
// on the film's nodes.
#pragma once
#include <cstdint>

#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

// One ball's (or film node's) contact with a feature of a triangulated surface (film or STL wall);
// its histories are in the slot's place of the stepper's ContactHistories (mesh_.slot_hist, mesh_.node_slot_hist).
struct MeshSlot {
  std::uint32_t surface = 0;          // 0 = the film when there is a bag, then the STL walls
  std::uint32_t key = 0;              // feature_key of the feature touched
  Vec3 n = Vec3::Zero();              // contact normal at the last step (towards the ball)
  Vec3 surface_velocity = Vec3::Zero();  // half-step velocity of the surface point (unit: m/s)
  double overlap = 0;                 // at the last step (unit: m)
};
// What a ball's film contact puts on the film's nodes: each touched feature's force split by its
// barycentric weights (a contact joining a patch's hits has one per hit: PatchBlend).
struct FilmLoad {
  Vec3 force[kPatchMembers] = {};     // force on the film at each contact point (unit: N)
  Vec3 weights[kPatchMembers] = {};
  std::uint32_t triangle[kPatchMembers] = {};
  std::uint8_t count = 0;
};
// A force on one of the film's nodes (unit: N).
struct NodePush {
  std::uint32_t node;
  Vec3 force;
};

}  // namespace bagdem
