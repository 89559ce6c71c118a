// The surface contacts component: the balls' (and the film nodes') contacts with triangulated
// surfaces, the bag's film (surface 0 with a bag) and STL walls: the surfaces, their candidate
// lists, the contact slots with their histories, the elastic energies and loads of this step.
// Its stage: triangles (surfaces.cpp); the film nodes' STL-wall contacts run in the film stage.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bagdem/mesh/triangle_mesh.hpp"
#include "bagdem/neighbour/mesh_candidates.hpp"
#include "bagdem/vec3.hpp"
#include "history.hpp"
#include "mesh_slot.hpp"

namespace bagdem {

struct Balls;
struct CavityFrame;
struct Film;
struct GuardValues;
struct Scene;
struct StepContext;

// Maximum number of triangle features one ball (or film node) touches at once: its contact slots.
inline constexpr std::size_t kMaxMeshContacts = 16;

struct SurfaceContacts {
  struct Surface {
    const TriangleMesh* mesh;   // topology (and, for STL walls, the vertices in the cavity frame)
    bool film;                  // vertices are the film's nodes (lab frame); otherwise mesh->vertices + cavity position
    int material;
    double reach;               // the film's half thickness, 0 for a wall (unit: m)
  };
  std::vector<Surface> surfaces;
  std::vector<MeshCandidates> cand;         // per surface
  std::vector<MeshSlot> slots;              // per ball: kMaxMeshContacts slots
  ContactHistories slot_hist;               // their histories
  std::vector<std::uint8_t> slot_count;     // per ball
  std::vector<FilmLoad> film_load;          // per ball slot, this step
  std::vector<double> elastic;              // per ball: its surface contacts' elastic energy (euler_terms; unit: J)
  std::vector<std::vector<NodePush>> film_push;  // per ball: their elastic forces on the film's nodes
  std::vector<Vec3> force_prev;             // per ball: force of the STL walls at the last step (unit: N)
  // A ball that cannot touch the film before travel reaches wake[p] (surfaces.cpp).
  bool asleep(std::size_t p) const { return !wake.empty() && travel < wake[p] && slot_count[p] == 0; }
  std::vector<double> wake;                 // per ball (unit: m)
  double travel = 0;                        // (unit: m)
  std::vector<std::int8_t> side;            // per ball: -1 inside the film (or an STL wall), +1 outside
  Vec3 cavity_at_build = Vec3::Zero();
  std::vector<Vec3> film_at_build;
  std::vector<MeshCandidates> node_cand;    // per surface: film nodes' candidate triangles (STL walls)
  std::vector<double> node_reach;           // per film node: half the film thickness (unit: m)
  std::vector<MeshSlot> node_slots;         // per film node: kMaxMeshContacts slots on STL walls
  ContactHistories node_slot_hist;          // their histories (no rolling: a node does not turn)
  std::vector<std::uint8_t> node_slot_count;
  std::vector<double> node_elastic;         // per film node: the elastic energy of its STL-wall contacts (unit: J)
  // Sized for the scene's surfaces and balls; each ball's side of the film (surfaces.cpp).
  void set_up(const Scene& scene, const Balls& balls, const Film& film);
  // The candidate lists from the positions of a build: the balls' (of these radii), the film
  // nodes', the cavity's (the neighbours stage, or a loaded checkpoint's stored ones).
  void build_candidates(const Scene& scene, const std::vector<double>& radius, const std::vector<Vec3>& balls,
                        const std::vector<Vec3>& film, const Vec3& cavity);
  // Whether the lists may not hold now: a ball (from x_at_build) or a film node moved more than
  // skin/2 since the build (relative to the cavity, for STL walls). tilt: how much farther a slope
  // moves a point of the cavity, |shear| x half its axial extent (0 without one) (unit: m).
  bool need_rebuild(const Scene& scene, const std::vector<Vec3>& balls, const std::vector<Vec3>& x_at_build,
                    const std::vector<Vec3>& film, const Vec3& cavity, double tilt) const;
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  // The candidate lists are not stored: they are rebuilt from the stored build positions, which
  // gives the same lists.
  template <class IO>
  void checkpoint(IO& io) {
    io.vec(slots), io.vec(slot_count), io.vec(elastic);
    slot_hist.fields(io);
    io.vec(side), io.vec(film_at_build), io.pod(cavity_at_build);
    io.vec(force_prev), io.vec(node_slots), io.vec(node_slot_count), io.vec(node_elastic);
    node_slot_hist.fields(io);
  }
};

// What the triangles stage works on: the step, the scene, the cavity's frame, the balls (their
// forces, torques and tallies gain the surfaces' share), the film's nodes (read: the surface the
// balls touch), the surface contacts, the balls' load moments on the structure
// (StructureCoupling::cavity_load) and the guards' values (overlap, a crossing, an overflow).
struct TriangleStage {
  const StepContext& ctx;
  const Scene& scene;
  const CavityFrame& frame;
  Balls& balls;
  const Film& film;
  SurfaceContacts& surfaces;
  std::vector<Vec3>& cavity_load;
  GuardValues& guard;
};
// The triangles stage (stage.hpp; surfaces.cpp): each ball against the triangulated surfaces.
void triangle_stage(const TriangleStage& s);

}  // namespace bagdem
