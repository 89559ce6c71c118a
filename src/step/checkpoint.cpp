// The complete dynamic state of a Stepper as a flat byte image (checkpoint/restart). Everything
// that influences later steps is stored exactly: particles, forces of the last step (the next half
// kick uses them), the Verlet list with its reference positions and contact histories, wall
// histories, tallies, time and counters. A resumed run is therefore bitwise identical to an
// uninterrupted one.
#include <cstring>
#include <stdexcept>

#include "stepper.hpp"

namespace bagdem {
namespace {

constexpr std::uint64_t kMagic = 0x6261676465'6d3036ULL;  // "bagdem06": format 6 (the surfaces' elastic energies, euler_terms)

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

// Each component's fields, one list used for both directions so they can never disagree.
template <class IO>
void fields(IO& io, Particles& p) {
  io.vec(p.x), io.vec(p.v), io.vec(p.w), io.vec(p.v_pred), io.vec(p.w_pred), io.vec(p.f), io.vec(p.t);
}
template <class IO>
void fields(IO& io, ParticleTallies& tally) {
  io.vec(tally.wall_force_prev), io.vec(tally.wall_impulse);
  io.vec(tally.wall_ang_impulse), io.vec(tally.work_cavity), io.vec(tally.diss_normal);
  io.vec(tally.diss_tangential), io.vec(tally.diss_rolling);
}
template <class IO>
void fields(IO& io, PairState& ps) {
  io.vec(ps.pairs.begin), io.vec(ps.pairs.partner);
  ps.hist.fields(io);
}

// The primary structure (empty vectors without one).
template <class IO>
void fields(IO& io, StructureState& st) {
  io.vec(st.q), io.vec(st.v), io.vec(st.v_pred), io.vec(st.a), io.vec(st.damping_prev), io.vec(st.load_prev);
  auto& c = st.scalars;  // field by field: the struct's padding bytes would make images differ
  io.pod(c.phase), io.pod(c.omega), io.pod(c.force), io.pod(c.released), io.pod(c.work_external);
  io.pod(c.work_contents), io.pod(c.dissipated);
  io.pod(st.load_now);
}

}  // namespace

// The whole state, in this order. The bag's film and the triangle contacts are empty vectors
// without them; their candidate lists are not stored: they are rebuilt from the stored build
// positions, which gives the same lists.
template <class IO>
void Stepper::state_fields(IO& io) {
  io.pod(step_), io.pod(nb_.builds), io.pod(cavity_.sums), io.pod(energy0_.potential), io.pod(energy0_.stored);
  io.pod(cavity_.now), io.pod(cavity_.prev);
  fields(io, p_);
  fields(io, p_.tally);
  fields(io, ps_);
  io.vec(nb_.x_at_build);
  walls_.hist.fields(io);
  io.vec(walls_.touch);
  io.vec(film_.x), io.vec(film_.v), io.vec(film_.v_pred), io.vec(film_.f), io.vec(film_.f_damp_prev);
  io.vec(film_.wall_force_prev);
  film_.wall_hist.fields(io);
  io.vec(film_.wall_touch);
  io.vec(film_.strings), io.pod(film_.tally);
  io.vec(mesh_.slots), io.vec(mesh_.slot_count), io.vec(mesh_.elastic);
  mesh_.slot_hist.fields(io);
  io.vec(mesh_.side), io.vec(mesh_.film_at_build), io.pod(mesh_.cavity_at_build);
  io.vec(mesh_.force_prev), io.vec(mesh_.node_slots), io.vec(mesh_.node_slot_count), io.vec(mesh_.node_elastic);
  mesh_.node_slot_hist.fields(io);
  fields(io, structure_);
  io.vec(structure_.cavity_load), io.pod(structure_.film_load_moments);
  io.pod(cavity_.pos_at_build), io.pod(cavity_.shear_at_build);
}

std::vector<char> Stepper::save_state() const {
  Writer w;
  w.pod(kMagic);
  w.pod(static_cast<std::uint64_t>(p_.size()));
  w.vec(p_.order);
  const_cast<Stepper&>(*this).state_fields(w);  // shared with load_state; the writer modifies nothing
  return std::move(w.out);
}

void Stepper::load_state(const std::vector<char>& image) {
  Reader r{image};
  std::uint64_t magic = 0, n = 0;
  r.pod(magic);
  r.pod(n);
  if (magic != kMagic)
    throw std::runtime_error("not a checkpoint of this bagdem version (format 6); rerun from the start");
  if (n != p_.size())
    throw std::runtime_error("checkpoint holds " + std::to_string(n) + " particles, the case " +
                             std::to_string(p_.size()));
  // The per-ball arrays are in the stepper's order, which follows from the case's initial state.
  std::vector<std::uint32_t> order;
  r.vec(order);
  if (order != p_.order) throw std::runtime_error("checkpoint holds the balls in another order than the case's initial state gives");
  state_fields(r);
  // What is derived from the pair list (first, per-pair buffers, the walls near each
  // ball), without a new broad-phase search.
  derive_pair_buffers();
  nb_.near_edge = near_skin_edge();  // as the run that saved the image found it at this step (end_drift)
  find_near_walls();
  if (!mesh_.surfaces.empty()) build_mesh_candidates(nb_.x_at_build, mesh_.film_at_build, mesh_.cavity_at_build);
}

}  // namespace bagdem
