// Test support: small scenes built in code (no case file), with the same model decisions as a case.
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/pair_laws.hpp"
#include "bagdem/particles.hpp"
#include "bagdem/scene.hpp"

namespace bagdem::testing {

class SceneBuilder {
 public:
  SceneBuilder() {
    s_.motion = make_fixed_motion();
    s_.gravity = Vec3::Zero();
    s_.cavity_lo = Vec3::Constant(-1);
    s_.cavity_hi = Vec3::Constant(1);
    s_.cavity_kind = "planes";
  }
  // Materials; the first is material 0. Units SI.
  SceneBuilder& material(const std::string& name, double rho, double E, double nu) {
    s_.materials.push_back({name, rho, E, nu});
    return *this;
  }
  // The same interaction for every pair of materials.
  SceneBuilder& interaction(double e, double mu = 0, double mu_r = 0) {
    inter_ = {e, mu, mu_r};
    return *this;
  }
  SceneBuilder& interaction(const Interaction& in) {  // any law (material.hpp)
    inter_ = in;
    return *this;
  }
  SceneBuilder& plane(const Vec3& point, const Vec3& inward_normal, int material = 0) {
    s_.wall_names.push_back("plane " + std::to_string(s_.walls.size()));
    s_.walls.push_back({WallKind::Plane, point, inward_normal.normalized(), 0, material});
    return *this;
  }
  SceneBuilder& box(const Vec3& lo, const Vec3& hi, int material = 0) {
    for (int k = 0; k < 3; ++k) {
      plane(lo, Vec3::Unit(k), material);
      plane(hi, -Vec3::Unit(k), material);
    }
    s_.cavity_lo = lo;
    s_.cavity_hi = hi;
    s_.cavity_kind = "box";
    s_.cavity_reference = 0.5 * (lo + hi);
    return *this;
  }
  // A bore: inner cylinder through `point` along `axis` (no caps; add planes for them).
  SceneBuilder& cylinder(const Vec3& point, const Vec3& axis, double radius, int material = 0) {
    s_.wall_names.push_back("cylinder " + std::to_string(s_.walls.size()));
    s_.walls.push_back({WallKind::Cylinder, point, axis.normalized(), radius, material});
    return *this;
  }
  SceneBuilder& bounds(const Vec3& lo, const Vec3& hi) {
    s_.cavity_lo = lo;
    s_.cavity_hi = hi;
    return *this;
  }
  SceneBuilder& particle(const Vec3& x, const Vec3& v, double radius, int material = 0,
                         const Vec3& w = Vec3::Zero()) {
    s_.particles.push_back({x, v, w, radius, material});
    return *this;
  }
  SceneBuilder& gravity(const Vec3& g) {
    s_.gravity = g;
    return *this;
  }
  SceneBuilder& motion(std::shared_ptr<const Motion> m) {
    s_.motion = std::move(m);
    return *this;
  }
  SceneBuilder& dt(double dt) {
    s_.dt = dt;
    return *this;
  }
  SceneBuilder& duration(double t) {
    s_.duration = t;
    return *this;
  }
  SceneBuilder& broad_phase(const std::string& name) {
    s_.broad_phase = name;
    return *this;
  }
  SceneBuilder& energy(bool on) {
    energy_ = on;
    return *this;
  }
  // Finishes: pair laws, model switches, skin (0.2 d_max), outputs. dt must be set.
  Scene build() {
    const std::size_t n = s_.materials.size();
    s_.laws = make_pair_laws(s_.materials, std::vector<Interaction>(n * n, inter_));
    decide_models(s_);
    s_.models.energy = energy_;
    double dmax = 0;
    for (const auto& p : s_.particles) dmax = std::max(dmax, 2 * p.radius);
    s_.skin = 0.2 * dmax;
    s_.max_overlap_fraction = 0.5;
    if (s_.duration == 0) s_.duration = 1000 * s_.dt;
    s_.output = {s_.duration, 100 * s_.dt, 100 * s_.dt, 0};
    return s_;
  }

 private:
  Scene s_;
  Interaction inter_{0.5, 0, 0};
  bool energy_ = true;
};

// Mass of a solid sphere (the engine's formula, include/bagdem/particles.hpp).
using bagdem::sphere_mass;

}  // namespace bagdem::testing
