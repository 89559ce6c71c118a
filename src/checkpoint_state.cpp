// The complete dynamic state of a Simulation as a flat byte image (checkpoint/restart). Everything
// that influences later steps is stored exactly: particles, forces of the last step (the next half
// kick uses them), the Verlet list with its reference positions and contact histories, wall
// histories, tallies, time and counters. A resumed run is therefore bitwise identical to an
// uninterrupted one.
#include <cstring>
#include <stdexcept>

#include "bagdem/stepper.hpp"

namespace bagdem {
namespace {

constexpr std::uint64_t kMagic = 0x6261676465'6d3034ULL;  // "bagdem04": format 4 (the wall histories per wall, then per ball)

struct Writer {
  std::vector<char> out;
  template <class T>
  void pod(const T& v) {
    const char* b = reinterpret_cast<const char*>(&v);
    out.insert(out.end(), b, b + sizeof(T));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod(static_cast<std::uint64_t>(v.size()));
    const char* b = reinterpret_cast<const char*>(v.data());
    out.insert(out.end(), b, b + v.size() * sizeof(T));
  }
};

struct Reader {
  const std::vector<char>& in;
  std::size_t at = 0;
  template <class T>
  void pod(T& v) {
    if (at + sizeof(T) > in.size()) throw std::runtime_error("checkpoint image is truncated");
    std::memcpy(static_cast<void*>(&v), in.data() + at, sizeof(T));
    at += sizeof(T);
  }
  template <class T>
  void vec(std::vector<T>& v) {
    std::uint64_t n = 0;
    pod(n);
    if (at + n * sizeof(T) > in.size()) throw std::runtime_error("checkpoint image is truncated");
    v.resize(n);
    std::memcpy(static_cast<void*>(v.data()), in.data() + at, n * sizeof(T));
    at += n * sizeof(T);
  }
};

// One list of every stored field, used for both directions so they can never disagree.
template <class IO, class Sim, class P, class T, class S, class C>
void fields(IO& io, std::uint64_t& step, std::uint64_t& builds, C& cavity_sums, double& pot0,
            double& ke0, P& p, T& tally, S& ps, std::vector<Vec3>& x_build,
            std::vector<TangentialHistory>& wall_tan, std::vector<RollingHistory>& wall_roll,
            std::vector<double>& wall_damp, std::vector<std::uint32_t>& wall_touch, CavityState& cav,
            CavityState& cav_prev) {
  io.pod(step), io.pod(builds), io.pod(cavity_sums), io.pod(pot0), io.pod(ke0);
  io.pod(cav), io.pod(cav_prev);
  io.vec(p.x), io.vec(p.v), io.vec(p.w), io.vec(p.v_pred), io.vec(p.w_pred), io.vec(p.f), io.vec(p.t);
  io.vec(tally.wall_force_prev), io.vec(tally.wall_impulse);
  io.vec(tally.wall_ang_impulse), io.vec(tally.work_cavity), io.vec(tally.diss_normal);
  io.vec(tally.diss_tangential), io.vec(tally.diss_rolling);
  io.vec(ps.pairs.begin), io.vec(ps.pairs.partner), io.vec(ps.tangential), io.vec(ps.rolling);
  io.vec(ps.damping_prev), io.vec(x_build), io.vec(wall_tan), io.vec(wall_roll), io.vec(wall_damp), io.vec(wall_touch);
}

// The primary structure (empty vectors without one).
template <class IO, class S>
void structure_fields(IO& io, S& st, std::vector<Vec3>& cavity_load, Vec3& film_load) {
  io.vec(st.q), io.vec(st.v), io.vec(st.v_pred), io.vec(st.a), io.vec(st.damping_prev), io.vec(st.load_prev);
  auto& c = st.scalars;  // field by field: the struct's padding bytes would make images differ
  io.pod(c.phase), io.pod(c.omega), io.pod(c.force), io.pod(c.released), io.pod(c.work_external);
  io.pod(c.work_contents), io.pod(c.dissipated);
  io.pod(st.load_now), io.vec(cavity_load), io.pod(film_load);
}

}  // namespace

// The bag's film and the triangle contacts (empty vectors without them). The candidate lists are
// not stored: they are rebuilt from the stored build positions, which gives the same lists.
template <class IO>
void Simulation::bag_state_fields(IO& io) {
  io.vec(film_.x), io.vec(film_.v), io.vec(film_.v_pred), io.vec(film_.f), io.vec(film_.f_damp_prev);
  io.vec(film_.wall_force_prev), io.vec(film_wall_tan_), io.vec(film_wall_damping_prev_), io.vec(film_wall_touch_);
  io.vec(strings_), io.pod(film_tally_);
  io.vec(slots_), io.vec(slot_count_), io.vec(side_), io.vec(film_at_build_), io.pod(cavity_at_build_);
  io.vec(mesh_force_prev_), io.vec(node_slots_), io.vec(node_slot_count_);
}

std::vector<char> Simulation::save_state() const {
  Writer w;
  w.pod(kMagic);
  w.pod(static_cast<std::uint64_t>(p_.size()));
  auto& self = const_cast<Simulation&>(*this);  // fields() is shared with load; nothing is modified
  w.vec(order_);
  fields<Writer, Simulation>(w, self.step_, self.builds_, self.cavity_sums_, self.potential0_,
                             self.kinetic_elastic0_, self.p_, self.tally_, self.ps_, self.x_at_build_,
                             self.wall_tan_, self.wall_roll_, self.wall_damping_prev_, self.wall_touch_, self.cavity_, self.cavity_prev_);
  self.bag_state_fields(w);
  structure_fields(w, self.structure_, self.cavity_load_, self.film_load_moments_);
  w.pod(cavity_pos_at_build_), w.pod(cavity_shear_at_build_);
  return std::move(w.out);
}

void Simulation::load_state(const std::vector<char>& image) {
  Reader r{image};
  std::uint64_t magic = 0, n = 0;
  r.pod(magic);
  r.pod(n);
  if (magic != kMagic)
    throw std::runtime_error("not a checkpoint of this bagdem version (format 4); rerun from the start");
  if (n != p_.size())
    throw std::runtime_error("checkpoint holds " + std::to_string(n) + " particles, the case " +
                             std::to_string(p_.size()));
  // The per-ball arrays are in the stepper's order, which follows from the case's initial state.
  std::vector<std::uint32_t> order;
  r.vec(order);
  if (order != order_) throw std::runtime_error("checkpoint holds the balls in another order than the case's initial state gives");
  fields<Reader, Simulation>(r, step_, builds_, cavity_sums_, potential0_, kinetic_elastic0_, p_,
                             tally_, ps_, x_at_build_, wall_tan_, wall_roll_, wall_damping_prev_, wall_touch_, cavity_, cavity_prev_);
  bag_state_fields(r);
  structure_fields(r, structure_, cavity_load_, film_load_moments_);
  r.pod(cavity_pos_at_build_), r.pod(cavity_shear_at_build_);
  // What is derived from the pair list (first, per-pair buffers, the walls near each
  // ball), without a new broad-phase search.
  derive_pair_buffers();
  near_edge_ = near_skin_edge();  // as the run that saved the image found it at this step (end_drift)
  find_near_walls();
  if (!surfaces_.empty()) build_mesh_candidates(x_at_build_, film_at_build_, cavity_at_build_);
}

}  // namespace bagdem
