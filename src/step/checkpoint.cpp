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

constexpr std::uint64_t kMagic = 0x6261676465'6d3039ULL;  // "bagdem09": format 9 (the film's tallies count the walls' stops)

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

}  // namespace

// The whole state: the stepper's own, then each component's checkpoint fields (its header), in
// this order. The bag's film and the triangle contacts are empty vectors without them.
template <class IO>
void Stepper::state_fields(IO& io) {
  io.pod(step_), io.pod(energy0_.potential), io.pod(energy0_.stored);
  p_.checkpoint(io);
  nb_.checkpoint(io);
  ps_.checkpoint(io);
  walls_.checkpoint(io);
  film_.checkpoint(io);
  mesh_.checkpoint(io);
  structure_.checkpoint(io);
  cavity_.checkpoint(io);
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
    throw std::runtime_error("not a checkpoint of this bagdem version (format 9); rerun from the start");
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
  neighbours_restored({scene_, frame(), p_, nb_, ps_, walls_, mesh_, film_, cavity_, structure_});
}

}  // namespace bagdem
