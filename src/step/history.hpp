// Contact histories: one layout for every kind of contact the stepper keeps (ball pairs, ball-wall,
// ball-triangle and film node-wall and node-triangle contacts): a slice per role, each indexed by the contact's slot, and empty when
// the scene does not model the role.
#pragma once
#include <cstddef>
#include <vector>

#include "bagdem/contact/mindlin.hpp"
#include "bagdem/contact/rolling.hpp"
#include "bagdem/vec3.hpp"

namespace bagdem {

// What a contact still held when it opened, as (normal, tangential, rolling) dissipation: the last
// half step of its forces' trapezoidal work (hertz.hpp, mindlin.hpp, rolling.hpp) and the energy
// its springs still stored. Both vanish with the overlap as dt -> 0; tallying them keeps the
// energy budget exact. n: normal from j to i; v_c, w_rel: half-step relative motion.
template <bool Tangential, bool Rolling>
Vec3 closing_tally(const Vec3& n, const Vec3& v_c, const Vec3& w_rel, double dt, double damping_prev,
                   const TangentialHistory* th, const RollingHistory* rh) {
  Vec3 d(-0.5 * damping_prev * v_c.dot(n) * dt, 0, 0);
  if constexpr (Tangential) d.y() = mindlin_energy(*th) - 0.5 * th->total.dot(v_c - v_c.dot(n) * n) * dt;
  if constexpr (Rolling) d.z() = rolling_energy(*rh) - 0.5 * rh->torque.dot(w_rel - w_rel.dot(n) * n) * dt;
  return d;
}

// The bytes of a tangential history that the law reads and writes: without the energy tally its
// force and stiffness, the first row (surface_contact_lanes). 7 in 8 histories straddle two cache
// lines, 3 in 8 of the first rows.
template <bool Energy>
constexpr std::size_t kTangentialBytes = Energy ? sizeof(TangentialHistory) : 4 * sizeof(double);

// One contact's histories, copied out of their slices (a slot that moves: surfaces.cpp).
struct ContactHistory {
  TangentialHistory tangential;
  RollingHistory rolling;
  double damping_prev = 0;
};

// The half-step relative motion of an opening contact (closing_tally's n, v_c, w_rel).
struct OpeningMotion {
  Vec3 n, v_c, w_rel;
};

struct ContactHistories {
  std::vector<TangentialHistory> tangential;  // the tangential spring (Mindlin-Deresiewicz)
  std::vector<RollingHistory> rolling;        // the rolling-resistance spring
  std::vector<double> damping_prev;           // normal damping force at the last step, for the energy tally (unit: N)

  // n slots, every history zero; a role's slice is empty when it is not modelled.
  void assign(std::size_t n, bool with_tangential, bool with_rolling, bool with_energy) {
    tangential.assign(with_tangential ? n : 0, {});
    rolling.assign(with_rolling ? n : 0, {});
    damping_prev.assign(with_energy ? n : 0, 0.0);
  }
  bool any_role() const { return !tangential.empty() || !rolling.empty() || !damping_prev.empty(); }
  // Slot k holds a history: its contact was closed at the last step.
  bool holds(std::size_t k) const {
    return (!tangential.empty() && tangential[k].stiffness != 0) || (!rolling.empty() && rolling[k].stiffness != 0) ||
           (!damping_prev.empty() && damping_prev[k] != 0);
  }
  // Slot k's histories (the roles not modelled as a fresh contact's), and slot k set to h.
  ContactHistory get(std::size_t k) const {
    ContactHistory h;
    if (!tangential.empty()) h.tangential = tangential[k];
    if (!rolling.empty()) h.rolling = rolling[k];
    if (!damping_prev.empty()) h.damping_prev = damping_prev[k];
    return h;
  }
  void set(std::size_t k, const ContactHistory& h) {
    if (!tangential.empty()) tangential[k] = h.tangential;
    if (!rolling.empty()) rolling[k] = h.rolling;
    if (!damping_prev.empty()) damping_prev[k] = h.damping_prev;
  }
  // Slot `to` takes slot `at` of `from` (a contact carried over to a new list).
  void carry(std::size_t to, const ContactHistories& from, std::size_t at) {
    if (!tangential.empty()) tangential[to] = from.tangential[at];
    if (!rolling.empty()) rolling[to] = from.rolling[at];
    if (!damping_prev.empty()) damping_prev[to] = from.damping_prev[at];
  }
  // The contact in slot k opened: with Energy, what it still held (closing_tally, from motion(), an
  // OpeningMotion; zero without); its histories cleared.
  template <bool Tangential, bool Rolling, bool Energy, class Motion>
  Vec3 open(std::size_t k, double dt, const Motion& motion) {
    Vec3 d = Vec3::Zero();
    if constexpr (Energy) {
      const OpeningMotion m = motion();
      d = closing_tally<Tangential, Rolling>(m.n, m.v_c, m.w_rel, dt, damping_prev[k],
                                             Tangential ? &tangential[k] : nullptr, Rolling ? &rolling[k] : nullptr);
      damping_prev[k] = 0.0;
    }
    if constexpr (Tangential) tangential[k] = {};
    if constexpr (Rolling) rolling[k] = {};
    return d;
  }
  void swap(ContactHistories& o) noexcept {
    tangential.swap(o.tangential);
    rolling.swap(o.rolling);
    damping_prev.swap(o.damping_prev);
  }
  // Checkpoints (checkpoint.cpp): the slices in this order.
  template <class IO>
  void fields(IO& io) {
    io.vec(tangential), io.vec(rolling), io.vec(damping_prev);
  }
};

}  // namespace bagdem
