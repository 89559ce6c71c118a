// The primary structure's part of the step (structure/primary.hpp): it is integrated with the
// contents by the same velocity Verlet.
//   kick_drift   v += dt/2 a, q += dt v, v_pred = v + dt/2 a         (StructureCoupling::drift)
//   move_cavity  cavity = (phi_b . q) e, velocity (phi_b . v_pred) e  (StructureCoupling::cavity)
//   contacts     the contents' load moments (m0, m1, m2), per ball and for the film
//   structure    Q = phi_f f(t) + G m - K q - C v_pred, a = M^-1 Q    (StructureCoupling::forces)
//   kick         v += dt/2 a                                          (StructureCoupling::kick)
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

// The bare steady state under F sin(theta + w t) at t = 0, from the responses to F sin(w t) and
// F cos(w t) (sin(theta + wt) = cos(theta) sin(wt) + sin(theta) cos(wt)). With q_s(t) = Re(Q e^{iwt})
// the sine response, the cosine response is Re(i Q e^{iwt}): at t = 0, q_c = v_s/w, v_c = -w q_s.
void bare_state_at(const Primary& P, double theta, double w, Eigen::VectorXd& q, Eigen::VectorXd& v) {
  Eigen::VectorXd qs, vs;
  P.bare_steady_state(P.amplitude, w, qs, vs);
  const double c = std::cos(theta), s = std::sin(theta);
  q = c * qs + s * (vs / w);
  v = c * vs - s * (w * qs);
}

// The state the structure is released in (see StructureCoupling::release) at drive frequency w,
// and the drive's phase then.
void release_state(const Primary& P, double w, Eigen::VectorXd& q, Eigen::VectorXd& v, double& phase) {
  q = P.q0, v = P.v0, phase = 0;
  if (!P.harmonic) return;
  Eigen::VectorXd qs, vs;
  if (P.start_steady) {
    P.bare_steady_state(P.amplitude, w, qs, vs);
    // u_b(theta) = Re(U e^{i theta}), U = phi_b . Q, Q = q(0) + i Im Q with Im Q = -v(0)/w.
    const Eigen::VectorXd& at = P.start_at.size() ? P.start_at : P.at_cavity;
    const std::complex<double> U(at.dot(qs), -at.dot(vs) / w);
    phase = std::abs(U) > 0 ? 0.5 * std::numbers::pi - std::arg(U) : 0.0;
    bare_state_at(P, phase, w, q, v);
  } else {
    bare_state_at(P, phase, w, qs, vs);
    for (std::size_t k = 0; k < P.size(); ++k) {
      if (!P.rigid_body[k]) continue;
      const auto K = static_cast<Eigen::Index>(k);
      q[K] += qs[K], v[K] += vs[K];
    }
  }
}

// Adds sign x (the bare steady state at phase theta) to the rigid-body DOFs (free-free beams).
void steady_rigid(const Primary& P, StructureState& S, double theta, double w, double sign) {
  if (!P.harmonic || w <= 0) return;
  Eigen::VectorXd q, v;
  bare_state_at(P, theta, w, q, v);
  for (std::size_t k = 0; k < P.size(); ++k) {
    if (!P.rigid_body[k]) continue;
    S.q[k] += sign * q[static_cast<Eigen::Index>(k)];
    S.v[k] += sign * v[static_cast<Eigen::Index>(k)];
  }
}
}  // namespace

void StructureCoupling::set_up(const Primary& P, std::size_t balls) {
  const std::size_t n = P.size();
  couple = true;
  tilt = P.follow_slope;
  tilt_extent = P.half_extent;
  load_axis = P.axis;
  load_dir = P.direction;
  cavity_load.assign(balls, Vec3::Zero());
  StructureState& S = *this;
  S.q.assign(n, 0.0), S.v.assign(n, 0.0), S.v_pred.assign(n, 0.0), S.a.assign(n, 0.0);
  S.damping_prev.assign(n, 0.0), S.load_prev.assign(n, 0.0);
  S.scalars = {};
  S.scalars.omega = 2 * std::numbers::pi * P.drive_frequency;
  // Held while the contents settle, already at the displacement it is released from (a decay's
  // initial displacement, a steady start's state); the cavity's displacement is counted from
  // there, so the settled contents see no jump of the walls at release.
  Eigen::VectorXd v0;
  release_state(P, S.scalars.omega, q_hold, v0, S.scalars.phase);
  VecMap(S.q.data(), S.q.size()) = q_hold;
}

// Settling is over: the structure starts moving, from q0, v0 (rest, or a decay's initial
// displacement). A harmonic drive starts at force phase 0 (no force jump) with the rigid-body modes
// of a free-free beam in their steady state (they have no stiffness to bring a drift back); with
// excitation.start = "steady" the whole structure starts in its bare steady state, at the phase at
// which the cavity's displacement is zero (no jump of the walls into the settled contents).
// Released at its own step: the time since release is 0.
void StructureCoupling::release(const Primary& P) {
  StructureState& S = *this;
  S.scalars.released = true;
  Eigen::VectorXd q0, v0;
  release_state(P, S.scalars.omega, q0, v0, S.scalars.phase);  // with the drive frequency of now (a sweep's first, rounded)
  VecMap(S.q.data(), S.q.size()) = q0;
  VecMap(S.v.data(), S.v.size()) = v0;
  restart_acceleration(P, 0.0);
}

void StructureCoupling::restart_acceleration(const Primary& P, double t) {
  for (std::size_t k = 0; k < v.size(); ++k) v_pred[k] = v[k];
  StepContext rest;
  rest.enter(StepMode::set_up, 0.0);
  forces(P, rest, t);
}

void StructureCoupling::set_drive_frequency(const Primary& P, double hz, double t) {
  if (!P.harmonic) return;
  StructureState& S = *this;
  const double w_new = 2 * std::numbers::pi * hz;
  if (S.scalars.released) {
    // Move the rigid-body DOFs from the old drive's steady state to the new one's.
    steady_rigid(P, S, S.scalars.phase, S.scalars.omega, -1.0);
    steady_rigid(P, S, S.scalars.phase, w_new, +1.0);
    S.scalars.omega = w_new;
    restart_acceleration(P, t);  // K q and C v changed with the rigid DOFs
    return;
  }
  S.scalars.omega = w_new;
}

void StructureCoupling::drift(double dt) {
  StructureState& S = *this;
  if (!S.scalars.released) return;
  const double h = 0.5 * dt;
  for (std::size_t k = 0; k < S.q.size(); ++k) {
    S.v[k] += h * S.a[k];
    S.q[k] += dt * S.v[k];
    S.v_pred[k] = S.v[k] + h * S.a[k];
  }
  S.scalars.phase += S.scalars.omega * dt;
}

CavityState StructureCoupling::cavity(const Primary& P) const {
  const StructureState& S = *this;
  // Displacement from where the structure was held while the contents settled (an expression:
  // no temporary vector, this runs every step).
  const auto dq = ConstVecMap(S.q.data(), S.q.size()) - q_hold;
  ConstVecMap vp(S.v_pred.data(), S.v_pred.size());
  CavityState c{P.at_cavity.dot(dq) * P.direction, P.at_cavity.dot(vp) * P.direction};
  if (P.follow_slope) {
    c.shear = P.slope_at_cavity.dot(dq) * P.direction;
    c.shear_rate = P.slope_at_cavity.dot(vp) * P.direction;
  }
  return c;
}

namespace {
double external_force(const Primary& P, const StructureState& S, double t_motion) {
  if (P.harmonic) return P.amplitude * std::sin(S.scalars.phase);
  return P.excitation ? P.excitation->force(t_motion) : 0.0;
}
}  // namespace

void StructureCoupling::forces(const Primary& P, const StepContext& ctx, double t) {
  StructureState& S = *this;
  // The contents' load moments, ball by ball, then the film's (fixed order).
  Vec3 m = film_load_moments;
  for (std::size_t p = 0; p < cavity_load.size(); ++p) m += cavity_load[p];
  if (!S.scalars.released) {
    S.load_now = m;
    return;
  }
  const std::size_t n = S.q.size();
  ConstVecMap q_(S.q.data(), n), v_(S.v_pred.data(), n), v_half(S.v.data(), n);
  // Scratch sized once (no allocation in the step); fd and Qc become this step's "previous".
  Eigen::VectorXd &Qc = scratch.load, &fd = scratch.damping, &Q = scratch.total;
  Qc.resize(static_cast<Eigen::Index>(n)), fd.resize(static_cast<Eigen::Index>(n)), Q.resize(static_cast<Eigen::Index>(n));
  if (all_load) Qc = *all_load;  // several dampers: the load of them all (step/dampers.hpp)
  else Qc.noalias() = P.load_fit * Eigen::Vector3d(m.x(), m.y(), m.z());
  const double f = external_force(P, S, t);
  fd = P.damping.cwiseProduct(v_);
  Q = P.at_force * f + Qc - P.stiffness.cwiseProduct(q_) - fd;
  VecMap acc(S.a.data(), n);
  acc.noalias() = P.mass_inverse * Q;
  VecMap fd_prev(S.damping_prev.data(), n), Qc_prev(S.load_prev.data(), n);
  if (ctx.stepping()) {
    // Trapezoidal work over this step's displacement dt v(n+1/2).
    S.scalars.work_external += 0.5 * (f + S.scalars.force) * ctx.dt * P.at_force.dot(v_half);
    S.scalars.work_contents += 0.5 * ctx.dt * (Qc + Qc_prev).dot(v_half);
    S.scalars.dissipated += 0.5 * ctx.dt * (fd + fd_prev).dot(v_half);
  }
  S.scalars.force = f;
  fd_prev = fd;
  Qc_prev = Qc;
  S.load_now = m;
}

const Eigen::VectorXd& StructureCoupling::damper_load(const Primary& P) {
  Vec3 m = film_load_moments;  // as forces sums them
  for (std::size_t p = 0; p < cavity_load.size(); ++p) m += cavity_load[p];
  own_load.noalias() = P.load_fit * Eigen::Vector3d(m.x(), m.y(), m.z());
  return own_load;
}

void StructureCoupling::kick(double dt) {
  StructureState& S = *this;
  if (!S.scalars.released) return;
  const double h = 0.5 * dt;
  for (std::size_t k = 0; k < S.v.size(); ++k) S.v[k] += h * S.a[k];
}

double StructureCoupling::energy(const Primary& P) const {
  const std::size_t n = q.size();
  ConstVecMap q_(q.data(), n), v_(v.data(), n);
  return 0.5 * v_.dot(P.mass * v_) + 0.5 * q_.dot(P.stiffness.cwiseProduct(q_));
}

StructureResponse StructureCoupling::response(const Primary& P) const {
  StructureResponse r;
  const std::size_t n = q.size();
  ConstVecMap q_(q.data(), n), v_(v.data(), n), a_(a.data(), n);
  r.displacement = P.at_response.dot(q_);
  r.velocity = P.at_response.dot(v_);
  r.acceleration = P.at_response.dot(a_);
  r.force = scalars.force;
  r.phase = scalars.phase;
  r.cavity = P.at_cavity.dot(q_);
  r.load = load_now.x();
  return r;
}

// ---- the structure stage and the stepper's calls --------------------------------------------------
double Stepper::since_release(bool stepping) const {
  return static_cast<double>(step_ + (stepping ? 1 : 0) - structure_.release_step) * scene_.dt;
}

void structure_stage(const StepContext& ctx, const Primary& P, double t, StructureCoupling& structure) { structure.forces(P, ctx, t); }

void Stepper::release_structure() { structure_.release(*scene_.primary); }

void Stepper::set_drive_frequency(double hz) {
  if (scene_.primary) structure_.set_drive_frequency(*scene_.primary, hz, since_release(false));
}

double Stepper::structure_energy() const { return scene_.primary ? structure_.energy(*scene_.primary) : 0.0; }

StructureResponse Stepper::structure_response() const {
  return scene_.primary ? structure_.response(*scene_.primary) : StructureResponse{};
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
  structure_.restart_acceleration(*scene_.primary, since_release(false));  // v_pred = v, and a
  const CavityState now = structure_.cavity(*scene_.primary);
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

}  // namespace bagdem
