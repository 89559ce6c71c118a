// The film component: the bag's film nodes (FilmNodes), its membrane, its strings, its contacts
// with the cavity's walls and its tallies; and its stage, film_stage (film.cpp), a free function of
// the views it needs (FilmStage).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "bagdem/bag/membrane.hpp"
#include "bagdem/contact/surface_law.hpp"
#include "bagdem/neighbour/broad_phase.hpp"
#include "bagdem/scene.hpp"
#include "bagdem/step/samples.hpp"
#include "bagdem/vec3.hpp"
#include "cavity_frame.hpp"
#include "history.hpp"
#include "surface_contacts.hpp"

namespace bagdem {

struct Film : FilmNodes {
  std::unique_ptr<Membrane> membrane;
  ContactHistories wall_hist;               // per node per wall (no rolling: a node does not turn)
  std::vector<std::uint32_t> wall_touch;    // per node: walls touched at the last step
  std::vector<std::uint32_t> wall_near;     // per node: the walls it may touch (find_film_walls_near)
  std::vector<double> wall_gap;             // per node: its least distance to those walls this step (+inf: none; unit: m)
  std::vector<double> stl_gap;              // per node: its distance to its deepest STL-wall hit this step (+inf: none; unit: m)
  std::vector<Vec3> stl_normal;             // that hit's normal, towards the node
  struct StringState {
    double damping_prev = 0;              // damping part of the tension at the last step (unit: N)
    Vec3 pull_prev = Vec3::Zero();        // pull on the tie at the last step (unit: N)
  };
  std::vector<StringState> strings;
  // Film-film contact (film_self.cpp; Bag::self_radius > 0): the pairs of nodes within two
  // spheres' radii and the skin at the last build, edge neighbours left out.
  std::unique_ptr<BroadPhase> self_broad;
  CandidatePairs self_pairs, self_found;
  std::vector<double> self_radii;                        // per node: Bag::self_radius
  std::vector<std::uint32_t> neighbour_begin, neighbour;  // CSR: each node's edge neighbours, ascending
  double deepest = 1e300;                   // smallest distance of a film node inside an STL wall (unit: m)
  struct Tallies {
    double work_cavity = 0;       // work of walls and string anchors on the film (unit: J)
    double diss_normal = 0, diss_tangential = 0;  // film-wall contacts (unit: J)
    double diss_damping = 0;      // membrane and string damping (unit: J)
    Vec3 impulse = Vec3::Zero();  // impulse the film gave the cavity since the last sample (unit: N s)
    Vec3 ang_impulse = Vec3::Zero();  // angular impulse about the cavity reference (unit: N m s)
    FilmSelfContact self;            // film-film contacts so far (film_self.cpp)
    std::uint64_t wall_stops = 0;    // steps at which the walls' stop held a node (film.cpp, film_wall_stops)
  } tally;
  // Sizes the film's arrays for the scene's bag (none without one), the nodes at their rest places.
  void set_up(const Scene& scene);
  // kick_drift's part: v += dt/2 F/m, x += dt v, v_pred = v + dt/2 F/m; returns the largest step's
  // square (unit: m^2). kick's: v += dt/2 F/m; returns whether every velocity is finite.
  double drift(double dt);
  bool kick(double dt);
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  template <class IO>
  void checkpoint(IO& io) {
    io.vec(x), io.vec(v), io.vec(v_pred), io.vec(f), io.vec(f_damp_prev), io.vec(wall_force_prev);
    wall_hist.fields(io);
    io.vec(wall_touch), io.vec(strings), io.pod(tally);
  }
};

// What the film stage works on: the step, the scene, the cavity's frame, the film, the surface
// contacts (the balls' loads on the film from the triangles stage; the nodes' STL-wall slots), and
// the film's load moments on the structure this step (StructureCoupling::film_load_moments).
struct FilmStage {
  const StepContext& ctx;
  const Scene& scene;
  const CavityFrame& frame;
  Film& film;
  SurfaceContacts& surfaces;
  Vec3& load_moments;
};

// The film stage (stage.hpp): the nodes' forces of this step, gravity, membrane, film-wall contacts,
// strings and the balls' loads, summed in a fixed order.
void film_stage(const FilmStage& s);

// Node k against the STL walls (surfaces.cpp): adds to the wall force on it F_wall, the angular
// impulse on the cavity L, the load moments, the dissipation (dn, dtg) and lowers `deepest` to
// its signed distance.
template <bool Tangential, bool Energy>
void film_node_stl_contacts(const FilmStage& s, std::size_t k, Vec3& F_wall, Vec3& L, Vec3& load, double& dn, double& dtg,
                            double& deepest);

// The walls within skin of each film node's reach at the build, `film` the nodes then and `cavity`
// the cavity's position then (with the shear then): film.wall_near, bit w for wall w. Until the
// next build neither moves more than skin/2, so the film-wall contacts skip the others.
void find_film_walls_near(Film& film, const Scene& scene, const CavityFrame& frame, const std::vector<Vec3>& at_build, const Vec3& cavity);

// Film-film contact (film_self.cpp): the pairs of nodes at `at_build` (the nodes at the build)
// within two spheres' radii and the skin, their forces this step, and their elastic energy.
void build_film_self_pairs(Film& film, const Scene& scene, const std::vector<Vec3>& at_build);
void film_self_contacts(const FilmStage& s);
double film_self_energy(const Scene& scene, const Film& film);

// Elastic energy held by the film: membrane and bending, strings, film-wall, STL-wall and
// film-film contacts.
double film_elastic_energy(const Scene& scene, const CavityFrame& frame, const Film& film, const SurfaceContacts& surfaces);

// Film node k against a wall or an STL wall (normal n towards the node, overlap): the film-wall
// law (R* = the film's contact radius, m* = the node's mass) against a surface moving at c_vel (end
// of step) and c_half (over it), histories in slot `at` of hist. The force on the node;
// dissipation into dn, dtg; `elastic` (when not null): the elastic part of the normal force.
template <bool Tangential, bool Energy>
BAGDEM_INLINE Vec3 film_node_contact(const FilmStage& s, std::size_t k, const Vec3& n, double overlap, const PairLaw& law, const Vec3& c_vel,
                                     const Vec3& c_half, ContactHistories& hist, std::size_t at, double& dn, double& dtg,
                                     double* elastic = nullptr) {
  const Film& film = s.film;
  ContactGeometry g;
  g.n = n, g.overlap = overlap, g.R_eff = s.scene.bag->contact_radius, g.m_eff = film.mass[k];
  g.arm_i = g.arm_j = 0;
  g.v_rel = film.v_pred[k] - c_vel;
  g.v_half = film.v[k] - c_half;
  g.w_half.setZero();
  Vec3 no_torque(0, 0, 0), diss(0, 0, 0);  // a node does not turn (arm 0)
  [[maybe_unused]] double no_tally = 0;
  const Vec3 Fc = surface_contact<Tangential, false, Energy>(g, law, s.ctx.dt, Energy ? hist.damping_prev[at] : no_tally,
                                                             Tangential ? &hist.tangential[at] : nullptr, nullptr, no_torque, diss, elastic);
  if constexpr (Energy) dn += diss.x(), dtg += diss.y();
  return Fc;
}

}  // namespace bagdem
