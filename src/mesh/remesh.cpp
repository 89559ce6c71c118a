// See remesh.hpp. A plain indexed triangle list with per-vertex triangle lists is enough here: every
// operation touches two triangles and the fans of four vertices (valence ~6), and the meshes are
// built once, before a run.
#include "remesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

namespace bagdem::detail {

namespace {

using Tri = std::array<std::uint32_t, 3>;
constexpr std::uint32_t kNone = 0xffffffffu;

double min_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  auto angle = [](const Vec3& p, const Vec3& q, const Vec3& r) {
    const Vec3 u = q - p, v = r - p;
    return std::atan2(u.cross(v).norm(), u.dot(v));
  };
  const double A = angle(a, b, c), B = angle(b, c, a);
  return std::min({A, B, std::numbers::pi - A - B});
}

class Remesher {
 public:
  Remesher(const TriangleMesh& m, double L, const std::function<Vec3(const Vec3&)>& project)
      : x_(m.vertices), tri_(m.triangles), tri_alive_(m.triangles.size(), 1), v_alive_(m.vertices.size(), 1),
        vt_(m.vertices.size()), hi_(4.0 / 3.0 * L), lo_(4.0 / 5.0 * L), project_(project) {
    for (std::uint32_t t = 0; t < tri_.size(); ++t) attach(t);
  }

  void split_long() {
    // Repeat: a split halves an edge, and an edge over 8/3 L needs two rounds.
    for (int round = 0; round < 64; ++round) {
      bool any = false;
      for (const auto& [a, b] : edges()) {
        if ((x_[a] - x_[b]).norm() <= hi_) continue;
        std::uint32_t t1, t2;
        if (!edge(a, b, t1, t2)) continue;
        split(a, b, t1, t2);
        any = true;
      }
      if (!any) return;
    }
  }

  void collapse_short() {
    for (const auto& [a, b] : edges())
      if (v_alive_[a] && v_alive_[b] && (x_[a] - x_[b]).norm() < lo_) try_collapse(a, b);
  }

  // Flips edge (a, b) to (c, d) where that brings the four valences closer to 6 (valence = 1).
  // mode 1: where the smaller of the two triangles' smallest angles grows (Delaunay-like, and
  // monotone, so it cannot cycle on a curved surface).
  void flip(int mode) {
    for (const auto& [a, b] : edges()) {
      std::uint32_t t1, t2;
      if (!edge(a, b, t1, t2)) continue;
      const std::uint32_t c = third(t1, a, b), d = third(t2, a, b);
      if (c == d || connected(c, d)) continue;
      const auto va = static_cast<long>(vt_[a].size()), vb = static_cast<long>(vt_[b].size());
      const auto vc = static_cast<long>(vt_[c].size()), vd = static_cast<long>(vt_[d].size());
      if (va <= 3 || vb <= 3) continue;
      // T1 = (a, b, c), T2 = (b, a, d): the quad a -> d -> b -> c; flipped: (a, d, c), (d, b, c).
      const Vec3 n1 = normal(a, b, c), n2 = normal(b, a, d);
      const Vec3 m1 = normal(a, d, c), m2 = normal(d, b, c);
      const Vec3 n = n1 + n2;
      if (!(m1.dot(n) > 0.5 * m1.norm() * n.norm() && m2.dot(n) > 0.5 * m2.norm() * n.norm())) continue;
      const double before = std::min(min_angle(x_[a], x_[b], x_[c]), min_angle(x_[b], x_[a], x_[d]));
      const double after = std::min(min_angle(x_[a], x_[d], x_[c]), min_angle(x_[d], x_[b], x_[c]));
      if (mode == 0) {
        auto sq = [](long v) { return v * v; };
        const long dev0 = sq(va - 6) + sq(vb - 6) + sq(vc - 6) + sq(vd - 6);
        const long dev1 = sq(va - 7) + sq(vb - 7) + sq(vc - 5) + sq(vd - 5);
        // Valence first, but never into a sliver.
        if (dev1 >= dev0 || after < std::min(before, 25.0 * std::numbers::pi / 180)) continue;
      } else if (!(after > before + 1e-9)) {
        continue;
      }
      set(t1, {a, d, c});
      set(t2, {d, b, c});
    }
  }

  // Moves every vertex along the surface towards the area-weighted centroid of its triangles
  // (which evens out areas, where the plain neighbour mean would shrink cells at irregular
  // vertices), half way per sweep, then onto the surface.
  void relax(int sweeps) {
    std::vector<Vec3> next(x_.size());
    for (int s = 0; s < sweeps; ++s) {
      for (std::uint32_t v = 0; v < x_.size(); ++v) {
        next[v] = x_[v];
        if (!v_alive_[v] || vt_[v].empty()) continue;
        Vec3 c = Vec3::Zero(), n = Vec3::Zero();
        double w = 0;
        for (std::uint32_t t : vt_[v]) {
          const Tri& q = tri_[t];
          const Vec3 cr = (x_[q[1]] - x_[q[0]]).cross(x_[q[2]] - x_[q[0]]);
          const double area = cr.norm();
          n += cr;
          c += area / 3.0 * (x_[q[0]] + x_[q[1]] + x_[q[2]]);
          w += area;
        }
        if (!(w > 0) || !(n.norm() > 0)) continue;
        n.normalize();
        Vec3 d = 0.5 * (c / w - x_[v]);
        d -= d.dot(n) * n;
        const Vec3 moved = project_(Vec3(x_[v] + d));
        // Keep the move only if no triangle of the fan turns over.
        bool ok = true;
        for (std::uint32_t t : vt_[v]) {
          Tri q = tri_[t];
          const Vec3 before = normal(q[0], q[1], q[2]);
          Vec3 p[3] = {x_[q[0]], x_[q[1]], x_[q[2]]};
          for (int k = 0; k < 3; ++k)
            if (q[k] == v) p[k] = moved;
          if (!((p[1] - p[0]).cross(p[2] - p[0]).dot(before) > 0)) ok = false;
        }
        if (ok) next[v] = moved;
      }
      x_.swap(next);
    }
  }

  TriangleMesh result() const {
    TriangleMesh m;
    std::vector<std::uint32_t> id(x_.size(), kNone);
    for (std::uint32_t v = 0; v < x_.size(); ++v)
      if (v_alive_[v] && !vt_[v].empty()) id[v] = static_cast<std::uint32_t>(m.vertices.size()), m.vertices.push_back(x_[v]);
    for (std::uint32_t t = 0; t < tri_.size(); ++t)
      if (tri_alive_[t]) m.triangles.push_back({id[tri_[t][0]], id[tri_[t][1]], id[tri_[t][2]]});
    build_topology(m);
    return m;
  }

 private:
  void attach(std::uint32_t t) {
    for (std::uint32_t v : tri_[t]) vt_[v].push_back(t);
  }
  void detach(std::uint32_t t) {
    for (std::uint32_t v : tri_[t]) {
      auto& l = vt_[v];
      l.erase(std::find(l.begin(), l.end(), t));
    }
  }
  void set(std::uint32_t t, const Tri& v) {
    detach(t);
    tri_[t] = v;
    attach(t);
  }
  std::uint32_t add(const Tri& v) {
    tri_.push_back(v);
    tri_alive_.push_back(1);
    attach(static_cast<std::uint32_t>(tri_.size() - 1));
    return static_cast<std::uint32_t>(tri_.size() - 1);
  }
  void kill(std::uint32_t t) {
    detach(t);
    tri_alive_[t] = 0;
  }
  Vec3 normal(std::uint32_t a, std::uint32_t b, std::uint32_t c) const { return (x_[b] - x_[a]).cross(x_[c] - x_[a]); }

  // Every edge once (a -> b in the triangle with a < b), in triangle order: a snapshot, since the
  // passes change the mesh as they go (each operation re-checks that its edge still exists).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges() const {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> e;
    for (std::uint32_t t = 0; t < tri_.size(); ++t)
      if (tri_alive_[t])
        for (int k = 0; k < 3; ++k)
          if (tri_[t][k] < tri_[t][(k + 1) % 3]) e.emplace_back(tri_[t][k], tri_[t][(k + 1) % 3]);
    return e;
  }
  // The triangles of edge (a, b): t1 runs a -> b, t2 runs b -> a.
  bool edge(std::uint32_t a, std::uint32_t b, std::uint32_t& t1, std::uint32_t& t2) const {
    t1 = t2 = kNone;
    if (!v_alive_[a] || !v_alive_[b]) return false;
    for (std::uint32_t t : vt_[a])
      for (int k = 0; k < 3; ++k)
        if (tri_[t][k] == a) {
          if (tri_[t][(k + 1) % 3] == b) t1 = t;
          if (tri_[t][(k + 2) % 3] == b) t2 = t;
        }
    return t1 != kNone && t2 != kNone;
  }
  std::uint32_t third(std::uint32_t t, std::uint32_t a, std::uint32_t b) const {
    for (std::uint32_t v : tri_[t])
      if (v != a && v != b) return v;
    return kNone;
  }
  bool connected(std::uint32_t a, std::uint32_t b) const {
    for (std::uint32_t t : vt_[a])
      for (std::uint32_t v : tri_[t])
        if (v == b) return true;
    return false;
  }
  void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (std::uint32_t t : vt_[v])
      for (std::uint32_t w : tri_[t])
        if (w != v && std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
  }

  void split(std::uint32_t a, std::uint32_t b, std::uint32_t t1, std::uint32_t t2) {
    const std::uint32_t c = third(t1, a, b), d = third(t2, a, b);
    const auto m = static_cast<std::uint32_t>(x_.size());
    x_.push_back(project_(Vec3(0.5 * (x_[a] + x_[b]))));
    v_alive_.push_back(1);
    vt_.emplace_back();
    // (a, b, c) -> (a, m, c) + (m, b, c); (b, a, d) -> (b, m, d) + (m, a, d): orientation kept.
    set(t1, {a, m, c});
    add({m, b, c});
    set(t2, {b, m, d});
    add({m, a, d});
  }

  void try_collapse(std::uint32_t a, std::uint32_t b) {
    std::uint32_t t1, t2;
    if (!edge(a, b, t1, t2)) return;
    const std::uint32_t c = third(t1, a, b), d = third(t2, a, b);
    if (c == d || vt_[c].size() <= 3 || vt_[d].size() <= 3 || vt_[a].size() + vt_[b].size() < 7) return;
    // Link condition (Dey et al. 1999): a and b share exactly the neighbours c and d, else the
    // collapse would pinch the surface.
    neighbours(a, na_);
    neighbours(b, nb_);
    int common = 0;
    for (std::uint32_t w : na_)
      if (std::find(nb_.begin(), nb_.end(), w) != nb_.end()) ++common;
    if (common != 2) return;
    const Vec3 p = project_(Vec3(0.5 * (x_[a] + x_[b])));
    for (const auto* list : {&na_, &nb_})
      for (std::uint32_t w : *list)
        if (w != a && w != b && (x_[w] - p).norm() > hi_) return;
    // No triangle of the two fans may turn by more than 60 degrees.
    for (std::uint32_t v : {a, b})
      for (std::uint32_t t : vt_[v]) {
        if (t == t1 || t == t2) continue;
        const Tri& q = tri_[t];
        Vec3 r[3] = {x_[q[0]], x_[q[1]], x_[q[2]]};
        for (int k = 0; k < 3; ++k)
          if (q[k] == a || q[k] == b) r[k] = p;
        const Vec3 before = normal(q[0], q[1], q[2]), after = (r[1] - r[0]).cross(r[2] - r[0]);
        if (!(after.dot(before) > 0.5 * after.norm() * before.norm())) return;
      }
    x_[b] = p;
    kill(t1);
    kill(t2);
    const std::vector<std::uint32_t> fan = vt_[a];
    for (std::uint32_t t : fan) {
      Tri q = tri_[t];
      for (auto& v : q)
        if (v == a) v = b;
      set(t, q);
    }
    v_alive_[a] = 0;
  }

  std::vector<Vec3> x_;
  std::vector<Tri> tri_;
  std::vector<char> tri_alive_, v_alive_;
  std::vector<std::vector<std::uint32_t>> vt_;
  double hi_, lo_;
  const std::function<Vec3(const Vec3&)>& project_;
  std::vector<std::uint32_t> na_, nb_;
};

}  // namespace

TriangleMesh remesh(const TriangleMesh& mesh, double L, const std::function<Vec3(const Vec3&)>& project,
                    int iterations) {
  if (!(L > 0)) throw std::invalid_argument("remesh: target edge length must be > 0");
  Remesher r(mesh, L, project);
  for (int it = 0; it < iterations; ++it) {
    r.split_long();
    r.collapse_short();
    r.flip(0);
    r.relax(3);
  }
  for (int it = 0; it < 4; ++it) {
    r.flip(1);
    r.relax(2);
  }
  r.flip(1);
  return r.result();
}

}  // namespace bagdem::detail
