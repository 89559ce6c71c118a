// The primary structure's part of the step (structure/primary.hpp): it is integrated with the
// contents by the same velocity Verlet.
//   kick_drift   v += dt/2 a, q += dt v, v_pred = v + dt/2 a         (structure_drift)
//   move_cavity  cavity = (phi_b . q) e, velocity (phi_b . v_pred) e  (structure_cavity)
//   contacts     the contents' load moments (m0, m1, m2), per ball and for the film
//   structure    Q = phi_f f(t) + G m - K q - C v_pred, a = M^-1 Q    (structure_forces)
//   kick         v += dt/2 a                                          (structure_kick)
// The structure is held at rest while the contents settle and released when settling ends, in the
// state the excitation asks for. Tallies (trapezoidal rule over each step's displacement, as the
// contacts' work): work of the external force, work of the contents' load, dissipation of C.
#include <cmath>
#include <numbers>

#include "stepper.hpp"
#include "bagdem/structure/excitation.hpp"

namespace bagdem {
namespace {
using VecMap = Eigen::Map<Eigen::VectorXd>;
using ConstVecMap = Eigen::Map<const Eigen::VectorXd>;
}  // namespace

void Stepper::set_up_structure() {
  if (!scene_.primary) return;
  const Primary& P = *scene_.primary;
  const std::size_t n = P.size();
  structure_.couple = true;
  structure_.tilt = P.follow_slope;
  structure_.tilt_extent = P.half_extent;
  structure_.load_axis = P.axis;
  structure_.load_dir = P.direction;
  structure_.cavity_load.assign(p_.size(), Vec3::Zero());
  StructureState& S = structure_;
  S.q.assign(n, 0.0), S.v.assign(n, 0.0), S.v_pred.assign(n, 0.0), S.a.assign(n, 0.0);
  S.damping_prev.assign(n, 0.0), S.load_prev.assign(n, 0.0);
  S.scalars = {};
  S.scalars.omega = 2 * std::numbers::pi * P.drive_frequency;
  // Held while the contents settle, already at the displacement it is released from (a decay's
  // initial displacement, a steady start's state); the cavity's displacement is counted from
  // there, so the settled contents see no jump of the walls at release.
  Eigen::VectorXd v;
  release_state(structure_.q_hold, v, S.scalars.phase);
  VecMap(S.q.data(), S.q.size()) = structure_.q_hold;
}

// The state the structure is released in (see release_structure) and the drive's phase then.
void Stepper::release_state(Eigen::VectorXd& q, Eigen::VectorXd& v, double& phase) const {
  const Primary& P = *scene_.primary;
  q = P.q0, v = P.v0, phase = 0;
  if (!P.harmonic) return;
  const double w = structure_.scalars.omega;
  Eigen::VectorXd qs, vs;
  if (P.start_steady) {
    P.bare_steady_state(P.amplitude, w, qs, vs);
    // u_b(theta) = Re(U e^{i theta}), U = phi_b . Q, Q = q(0) + i Im Q with Im Q = -v(0)/w.
    const std::complex<double> U(P.at_cavity.dot(qs), -P.at_cavity.dot(vs) / w);
    phase = std::abs(U) > 0 ? 0.5 * std::numbers::pi - std::arg(U) : 0.0;
    bare_state_at(phase, w, q, v);
  } else {
    bare_state_at(phase, w, qs, vs);
    for (std::size_t k = 0; k < P.size(); ++k) {
      if (!P.rigid_body[k]) continue;
      const auto K = static_cast<Eigen::Index>(k);
      q[K] += qs[K], v[K] += vs[K];
    }
  }
}

// Settling is over: the structure starts moving, from q0, v0 (rest, or a decay's initial
// displacement). A harmonic drive starts at force phase 0 (no force jump) with the rigid-body modes
// of a free-free beam in their steady state (they have no stiffness to bring a drift back); with
// excitation.start = "steady" the whole structure starts in its bare steady state, at the phase at
// which the cavity's displacement is zero (no jump of the walls into the settled contents).
void Stepper::release_structure() {
  StructureState& S = structure_;
  S.scalars.released = true;
  Eigen::VectorXd q, v;
  release_state(q, v, S.scalars.phase);  // with the drive frequency of now (a sweep's first, rounded)
  VecMap(S.q.data(), S.q.size()) = q;
  VecMap(S.v.data(), S.v.size()) = v;
  restart_acceleration();
}

// From one harmonic state to another at the present force phase theta: q += Re((B - A) e^{i theta}),
// v += Re(i (w_b B - w_a A) e^{i theta}) (A at w_a, B at w_b: complex amplitudes, q = Re(Q e^{i theta})),
// between steps. The contents' places move with the cavity's walls, each by the jump of the wall
// displacement at it (the slope's shear included), so no overlap changes; their velocities stay
// (the walls' velocity jumps against them). The places kept from the last neighbour build move by
// the jump's translation: its shear part (each place's own, up to the cavity's half length times
// the shear's jump) counts as travel, so every skin and sleeping bound still holds. The step after
// counts no work for the jump (the cavity's last position moves with it).
void Stepper::jump_harmonic(const Eigen::VectorXcd& A, double w_a, const Eigen::VectorXcd& B, double w_b) {
  if (!scene_.primary || !structure_.scalars.released) return;
  StructureState& S = structure_;
  const std::complex<double> e = std::polar(1.0, S.scalars.phase), i(0, 1);
  const auto n = static_cast<Eigen::Index>(S.q.size());
  VecMap(S.q.data(), n) += ((B - A) * e).real();
  VecMap(S.v.data(), n) += ((i * w_b * B - i * w_a * A) * e).real();
  const CavityState was = cavity_.now;
  restart_acceleration();  // v_pred = v, and a
  const CavityState now = structure_cavity();
  auto moved = [&](const Vec3& x) {
    const double s = structure_.tilt ? (x - was.position - scene_.cavity_reference).dot(structure_.load_axis) : 0.0;
    return Vec3(now.position - was.position + s * (now.shear - was.shear));
  };
  const Vec3 rigid = now.position - was.position;
  for (std::size_t k = 0; k < p_.size(); ++k) p_.x[k] += moved(p_.x[k]), nb_.x_at_build[k] += rigid;
  for (std::size_t k = 0; k < film_.size(); ++k) film_.x[k] += moved(film_.x[k]);
  for (Vec3& x : mesh_.film_at_build) x += rigid;
  mesh_.cavity_at_build += rigid, cavity_.pos_at_build += rigid;
  const double sheared = structure_.tilt ? 2 * structure_.tilt_extent * (now.shear - was.shear).norm() : 0.0;
  nb_.travel += sheared, mesh_.travel += 2 * sheared;
  cavity_.prev.position += rigid, cavity_.prev.shear += now.shear - was.shear;
  cavity_.now = now;
}

// a from the present state, the contents' load of the last step and the force now (in set-up
// mode, so nothing is tallied and the previous-step values restart from here).
void Stepper::restart_acceleration() {
  for (std::size_t k = 0; k < structure_.v.size(); ++k) structure_.v_pred[k] = structure_.v[k];
  const StepContext keep = ctx_;
  ctx_.enter(StepMode::set_up, scene_.dt);
  structure_forces();
  ctx_ = keep;
}

// The bare steady state under F sin(theta + w t) at t = 0, from the responses to F sin(w t) and
// F cos(w t) (sin(theta + wt) = cos(theta) sin(wt) + sin(theta) cos(wt)). With q_s(t) = Re(Q e^{iwt})
// the sine response, the cosine response is Re(i Q e^{iwt}): at t = 0, q_c = v_s/w, v_c = -w q_s.
void Stepper::bare_state_at(double theta, double w, Eigen::VectorXd& q, Eigen::VectorXd& v) const {
  const Primary& P = *scene_.primary;
  Eigen::VectorXd qs, vs;
  P.bare_steady_state(P.amplitude, w, qs, vs);
  const double c = std::cos(theta), s = std::sin(theta);
  q = c * qs + s * (vs / w);
  v = c * vs - s * (w * qs);
}

// Adds sign x (the bare steady state at phase theta) to the rigid-body DOFs (free-free beams).
void Stepper::steady_rigid(double theta, double w, double sign) {
  const Primary& P = *scene_.primary;
  if (!P.harmonic || w <= 0) return;
  Eigen::VectorXd q, v;
  bare_state_at(theta, w, q, v);
  for (std::size_t k = 0; k < P.size(); ++k) {
    if (!P.rigid_body[k]) continue;
    structure_.q[k] += sign * q[static_cast<Eigen::Index>(k)];
    structure_.v[k] += sign * v[static_cast<Eigen::Index>(k)];
  }
}

void Stepper::set_drive_frequency(double hz) {
  if (!scene_.primary || !scene_.primary->harmonic) return;
  StructureState& S = structure_;
  const double w_new = 2 * std::numbers::pi * hz;
  if (S.scalars.released) {
    // Move the rigid-body DOFs from the old drive's steady state to the new one's.
    steady_rigid(S.scalars.phase, S.scalars.omega, -1.0);
    steady_rigid(S.scalars.phase, w_new, +1.0);
    S.scalars.omega = w_new;
    restart_acceleration();  // K q and C v changed with the rigid DOFs
    return;
  }
  S.scalars.omega = w_new;
}

void Stepper::structure_drift() {
  StructureState& S = structure_;
  if (!S.scalars.released) return;
  const double dt = scene_.dt, h = 0.5 * dt;
  for (std::size_t k = 0; k < S.q.size(); ++k) {
    S.v[k] += h * S.a[k];
    S.q[k] += dt * S.v[k];
    S.v_pred[k] = S.v[k] + h * S.a[k];
  }
  S.scalars.phase += S.scalars.omega * dt;
}

CavityState Stepper::structure_cavity() const {
  const Primary& P = *scene_.primary;
  const StructureState& S = structure_;
  // Displacement from where the structure was held while the contents settled (an expression:
  // no temporary vector, this runs every step).
  const auto dq = ConstVecMap(S.q.data(), S.q.size()) - structure_.q_hold;
  ConstVecMap v(S.v_pred.data(), S.v_pred.size());
  CavityState c{P.at_cavity.dot(dq) * P.direction, P.at_cavity.dot(v) * P.direction};
  if (P.follow_slope) {
    c.shear = P.slope_at_cavity.dot(dq) * P.direction;
    c.shear_rate = P.slope_at_cavity.dot(v) * P.direction;
  }
  return c;
}

double Stepper::external_force(double t_motion) const {
  const Primary& P = *scene_.primary;
  if (P.harmonic) return P.amplitude * std::sin(structure_.scalars.phase);
  return P.excitation ? P.excitation->force(t_motion) : 0.0;
}

void Stepper::structure_forces() {
  const Primary& P = *scene_.primary;
  StructureState& S = structure_;
  // The contents' load moments, ball by ball, then the film's (fixed order).
  Vec3 m = structure_.film_load_moments;
  for (std::size_t p = 0; p < p_.size(); ++p) m += structure_.cavity_load[p];
  if (!S.scalars.released) {
    S.load_now = m;
    return;
  }
  const std::size_t n = S.q.size();
  ConstVecMap q(S.q.data(), n), v(S.v_pred.data(), n), v_half(S.v.data(), n);
  // Scratch sized once (no allocation in the step); fd and Qc become this step's "previous".
  Eigen::VectorXd &Qc = structure_.scratch.load, &fd = structure_.scratch.damping, &Q = structure_.scratch.total;
  Qc.resize(static_cast<Eigen::Index>(n)), fd.resize(static_cast<Eigen::Index>(n)), Q.resize(static_cast<Eigen::Index>(n));
  Qc.noalias() = P.load_fit * Eigen::Vector3d(m.x(), m.y(), m.z());
  // Time since release at the end of this step (at release itself: 0).
  const double t = static_cast<double>(step_ + (ctx_.stepping() ? 1 : 0) - structure_.release_step) * scene_.dt;
  const double f = external_force(t);
  fd = P.damping.cwiseProduct(v);
  Q = P.at_force * f + Qc - P.stiffness.cwiseProduct(q) - fd;
  VecMap a(S.a.data(), n);
  a.noalias() = P.mass_inverse * Q;
  VecMap fd_prev(S.damping_prev.data(), n), Qc_prev(S.load_prev.data(), n);
  if (ctx_.stepping()) {
    // Trapezoidal work over this step's displacement dt v(n+1/2).
    S.scalars.work_external += 0.5 * (f + S.scalars.force) * ctx_.dt * P.at_force.dot(v_half);
    S.scalars.work_contents += 0.5 * ctx_.dt * (Qc + Qc_prev).dot(v_half);
    S.scalars.dissipated += 0.5 * ctx_.dt * (fd + fd_prev).dot(v_half);
  }
  S.scalars.force = f;
  fd_prev = fd;
  Qc_prev = Qc;
  S.load_now = m;
}

void Stepper::structure_kick() {
  StructureState& S = structure_;
  if (!S.scalars.released) return;
  const double h = 0.5 * scene_.dt;
  for (std::size_t k = 0; k < S.v.size(); ++k) S.v[k] += h * S.a[k];
}

double Stepper::structure_energy() const {
  if (!scene_.primary) return 0.0;
  const Primary& P = *scene_.primary;
  const std::size_t n = structure_.q.size();
  ConstVecMap q(structure_.q.data(), n), v(structure_.v.data(), n);
  return 0.5 * v.dot(P.mass * v) + 0.5 * q.dot(P.stiffness.cwiseProduct(q));
}

StructureResponse Stepper::structure_response() const {
  StructureResponse r;
  if (!scene_.primary) return r;
  const Primary& P = *scene_.primary;
  const std::size_t n = structure_.q.size();
  ConstVecMap q(structure_.q.data(), n), v(structure_.v.data(), n), a(structure_.a.data(), n);
  r.displacement = P.at_response.dot(q);
  r.velocity = P.at_response.dot(v);
  r.acceleration = P.at_response.dot(a);
  r.force = structure_.scalars.force;
  r.phase = structure_.scalars.phase;
  r.cavity = P.at_cavity.dot(q);
  r.load = structure_.load_now.x();
  return r;
}

}  // namespace bagdem
