// The film component: the bag's film nodes (FilmNodes), its membrane, its strings, its contacts
// with the cavity's walls and its tallies. Its stage: film (film.cpp).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "bagdem/bag/membrane.hpp"
#include "bagdem/step/samples.hpp"
#include "bagdem/vec3.hpp"
#include "history.hpp"

namespace bagdem {

struct Film : FilmNodes {
  std::unique_ptr<Membrane> membrane;
  ContactHistories wall_hist;               // per node per wall (no rolling: a node does not turn)
  std::vector<std::uint32_t> wall_touch;    // per node: walls touched at the last step
  std::vector<std::uint32_t> wall_near;     // per node: the walls it may touch (find_film_walls_near)
  struct StringState {
    double damping_prev = 0;              // damping part of the tension at the last step (unit: N)
    Vec3 pull_prev = Vec3::Zero();        // pull on the tie at the last step (unit: N)
  };
  std::vector<StringState> strings;
  double deepest = 1e300;                   // smallest distance of a film node inside a wall (unit: m)
  struct Tallies {
    double work_cavity = 0;       // work of walls and string anchors on the film (unit: J)
    double diss_normal = 0, diss_tangential = 0;  // film-wall contacts (unit: J)
    double diss_damping = 0;      // membrane and string damping (unit: J)
    Vec3 impulse = Vec3::Zero();  // impulse the film gave the cavity since the last sample (unit: N s)
    Vec3 ang_impulse = Vec3::Zero();  // angular impulse about the cavity reference (unit: N m s)
  } tally;
  // Its checkpoint fields (step/checkpoint.cpp): one list for writing and reading, so the two
  // cannot disagree. IO: pod(x) and vec(v).
  template <class IO>
  void checkpoint(IO& io) {
    io.vec(x), io.vec(v), io.vec(v_pred), io.vec(f), io.vec(f_damp_prev), io.vec(wall_force_prev);
    wall_hist.fields(io);
    io.vec(wall_touch), io.vec(strings), io.pod(tally);
  }
};

}  // namespace bagdem
