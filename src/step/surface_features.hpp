// The triangles stage's contact finding (surfaces.cpp): the features a ball or a film node touches,
// one contact per patch (joined: PatchBlend), and the slots whose histories they continue.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/neighbour/mesh_candidates.hpp"
#include "history.hpp"
#include "mesh_slot.hpp"

namespace bagdem::surface_contacts {

// A hit joined into a patch's contact (PatchBlend): where it touches, its own normal, and its
// parts of the force (c: of the normal force, share: of the tangential force and the velocities).
struct PatchMember {
  std::uint32_t triangle;
  Vec3 weights, point, n;
  double c, share;
};

// A contact found this step: the feature hit (a patch's deepest), the normal towards the body, the
// overlap, and the slot of the previous step whose history it continues (-1: new). A contact
// joining several hits of a patch (members > 1) has the joined normal and overlap, `scale` and
// each hit in `member`, deepest first.
struct Found {
  std::uint32_t surface;
  MeshHit hit;
  Vec3 n;
  double overlap;
  int from;
  std::uint8_t members = 1;
  double scale = 1;
  PatchMember member[kPatchMembers];  // the first `members` when members > 1 (else unset)
};

// The contact law's force Fc (normal part F_n along fd.n) as each hit's share: hit i presses
// F_n c_i along its own normal and carries share_i of the tangential force; the sum is
// F_n scale n + F_t, the gradient of the joined contact's energy.
inline void member_forces(const Found& fd, const Vec3& Fc, Vec3* out) {
  const double Fn = Fc.dot(fd.n);
  const Vec3 Ft = Fc - Fn * fd.n;
  for (std::size_t i = 0; i < fd.members; ++i) out[i] = Fn * fd.member[i].c * fd.member[i].n + fd.member[i].share * Ft;
}

// The film's part of a joined contact's inverse mass: sum over the touched nodes k of
// |sum_i c_i w_ik n_i|^2 / m_k (hits sharing a node add their pushes on it first).
inline double joined_inverse_mass(const Found& fd, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                  const std::vector<double>& inv_mass) {
  std::uint32_t node[3 * kPatchMembers];
  Vec3 push[3 * kPatchMembers];
  std::size_t n = 0;
  for (std::size_t i = 0; i < fd.members; ++i)
    for (int a = 0; a < 3; ++a) {
      const std::uint32_t k = triangles[fd.member[i].triangle][a];
      const Vec3 g = fd.member[i].c * fd.member[i].weights[a] * fd.member[i].n;
      std::size_t j = 0;
      while (j < n && node[j] != k) ++j;
      if (j == n) node[n] = k, push[n++] = g;
      else push[j] += g;
    }
  double inv = 0;
  for (std::size_t j = 0; j < n; ++j) inv += push[j].squaredNorm() * inv_mass[node[j]];
  return inv;
}

// Normal and overlap of a body at x on `side` of a surface (-1: against its triangles' normals),
// touching the hit's feature within `reach`. The side is judged by the touched triangle's normal
// (exact for a face; for an edge or vertex, right whenever the centre is in that feature's region
// on its own side). Returns false when the centre is beyond the mid-surface.
inline bool oriented(const Vec3& x, const std::vector<Vec3>& vx, const std::array<std::uint32_t, 3>& tri, const TriangleHit& h,
              double side, double reach, Vec3& n, double& overlap) {
  const Vec3 normal = (vx[tri[1]] - vx[tri[0]]).cross(vx[tri[2]] - vx[tri[0]]).normalized();
  const Vec3 d = x - h.point;
  const double dist = std::sqrt(h.distance2);
  const bool own_side = side * d.dot(normal) >= 0;
  n = dist > 1e-12 * reach ? Vec3((own_side ? 1.0 : -1.0) * d / dist) : Vec3(side * normal);
  overlap = reach - (own_side ? dist : -dist);
  return own_side;
}

// Histories: the same feature keeps its slot; a new feature takes over the closed slot of the same
// surface whose normal is closest to its own (within 60 degrees), so a contact moving across a
// triangulation (face -> edge -> next face) keeps its friction spring. `taken` marks the slots
// continued.
inline void match_slots(const MeshSlot* slot, std::size_t n_prev, Found* found, std::size_t nf, bool* taken) {
  for (std::size_t f = 0; f < nf; ++f)
    for (std::size_t k = 0; k < n_prev; ++k)
      if (!taken[k] && slot[k].surface == found[f].surface && slot[k].key == found[f].hit.key) {
        found[f].from = static_cast<int>(k);
        taken[k] = true;
        break;
      }
  for (std::size_t f = 0; f < nf; ++f) {
    if (found[f].from >= 0) continue;
    double best = 0.5;
    for (std::size_t k = 0; k < n_prev; ++k) {
      if (taken[k] || slot[k].surface != found[f].surface) continue;
      const double c = slot[k].n.dot(found[f].n);
      if (c > best) {
        best = c;
        found[f].from = static_cast<int>(k);
      }
    }
    if (found[f].from >= 0) taken[found[f].from] = true;
  }
}

// One contact per patch (contact/sphere_triangle.hpp, join_patches), in place.
inline void keep_patches(std::vector<Found>& hits) {
  if (hits.size() < 2) return;  // most balls touch one feature
  thread_local std::vector<Vec3> n;
  thread_local std::vector<double> overlap;
  thread_local std::vector<PatchContact> patch;
  thread_local std::vector<Found> kept;
  const std::size_t count = std::min(hits.size(), kMaxPatchHits);
  n.resize(count), overlap.resize(count), patch.resize(count);
  for (std::size_t i = 0; i < count; ++i) n[i] = hits[i].n, overlap[i] = hits[i].overlap;
  const std::size_t np = join_patches(n.data(), overlap.data(), count, patch.data());
  if (np == hits.size()) return;  // every hit a patch of its own, in its place
  kept.clear();
  for (std::size_t k = 0; k < np; ++k) {
    const PatchContact& c = patch[k];
    Found fd = hits[c.member[0]];
    if (c.count > 1) {
      fd.members = static_cast<std::uint8_t>(c.count);
      fd.n = c.blend.n, fd.overlap = c.blend.overlap, fd.scale = c.blend.scale;
      for (std::size_t j = 0; j < c.count; ++j) {
        const TriangleHit& h = hits[c.member[j]].hit.hit;
        fd.member[j] = {hits[c.member[j]].hit.triangle, h.weights, h.point, n[c.member[j]], c.blend.c[j], c.blend.share[j]};
      }
    }
    kept.push_back(fd);
  }
  hits.assign(kept.begin(), kept.end());
}

// The point `i` of a surface contact (a ball, or a film node) against the triangulated surfaces:
// where it is in surface s's frame, the vertices there, its reach and its side (-1: against the
// triangles' normals).
struct PointView {
  Vec3 x;
  const std::vector<Vec3>* vertices;
  double reach, side;
};

// Step 1 of a point's surface contacts, one feature finder for balls and film nodes: the features
// it touches now. The closest points of its candidate triangles (cand[s], entries of point i)
// within reach, one per feature (select_mesh_contacts), oriented, one per patch (keep_patches);
// at most kMax into found, in surface order. view(s) places the point (PointView); touched(s,
// overlap, reach, own_side) sees each contact found; full() is told when one did not fit.
// gap (when not null): the least distance of a candidate beyond the point's reach (HUGE_VAL
// without candidates), rounded down.
template <std::size_t kMax, class Surfaces, class View, class Touched, class Full>
inline std::size_t find_features(const Surfaces& surfaces, const std::vector<MeshCandidates>& cand, std::size_t i,
                          const View& view, const Touched& touched, const Full& full, Found* found,
                          double* gap = nullptr) {
  thread_local std::vector<MeshHit> hits;
  thread_local std::vector<Found> patch;
  std::size_t nf = 0;
  if (gap) *gap = HUGE_VAL;
  for (std::uint32_t s = 0; s < surfaces.size(); ++s) {
    const MeshCandidates& c = cand[s];
    if (c.begin.empty() || c.begin[i] == c.begin[i + 1]) continue;  // empty: no candidate list for this surface
    const PointView pv = view(s);
    const auto& mesh = *surfaces[s].mesh;
    const std::vector<Vec3>& vx = *pv.vertices;
    hits.clear();
    double nearest2 = HUGE_VAL;
    // The candidates kLanes at a time by their distance (triangle_distance2); those that may lie
    // within reach again by the exact closest point, which decides.
    const double reach2 = pv.reach * pv.reach, pass_over = reach2 * (1.0 + 1e-6);
    const Lanes3 x{splat<Lanes>(pv.x.x()), splat<Lanes>(pv.x.y()), splat<Lanes>(pv.x.z())};
    for (std::uint32_t e0 = c.begin[i]; e0 < c.begin[i + 1]; e0 += kLanes) {
      const std::uint32_t last = c.begin[i + 1] - 1;
      std::uint32_t t[kLanes];
      for (int l = 0; l < kLanes; ++l) t[l] = c.triangle[std::min<std::uint32_t>(e0 + l, last)];
      auto corner = [&](int k) {
        const double* p[kLanes] = {vx[mesh.triangles[t[0]][k]].data(), vx[mesh.triangles[t[1]][k]].data(),
                                   vx[mesh.triangles[t[2]][k]].data(), vx[mesh.triangles[t[3]][k]].data()};
        return gather3(p);
      };
      const Lanes d2 = triangle_distance2(x, corner(0), corner(1), corner(2));
      for (int l = 0; l < kLanes && e0 + l <= last; ++l) {
        if (d2[l] >= pass_over) {
          nearest2 = std::min(nearest2, d2[l]);
          continue;
        }
        const auto& tri = mesh.triangles[t[l]];
        const TriangleHit h = closest_point_on_triangle(pv.x, vx[tri[0]], vx[tri[1]], vx[tri[2]]);
        nearest2 = std::min(nearest2, h.distance2);
        if (h.distance2 < reach2) hits.push_back({t[l], 0, h});
      }
    }
    // 1e-9 of the reach: far above the rounding of the distances (1e-16 of them), far below a step.
    if (gap) *gap = std::min(*gap, std::sqrt(nearest2) - pv.reach * (1.0 + 1e-9));
    if (hits.empty()) continue;
    select_mesh_contacts(mesh, hits);
    patch.clear();
    for (const MeshHit& mh : hits) {
      Vec3 n;
      double overlap;
      const bool own_side = oriented(pv.x, vx, mesh.triangles[mh.triangle], mh.hit, pv.side, pv.reach, n, overlap);
      touched(s, overlap, pv.reach, own_side);
      Found fd;
      fd.surface = s, fd.hit = mh, fd.n = n, fd.overlap = overlap, fd.from = -1;
      patch.push_back(fd);
    }
    keep_patches(patch);
    for (const Found& fd : patch) {
      if (nf == kMax) {
        full();
        break;
      }
      found[nf++] = fd;
    }
  }
  return nf;
}

// Step 2: the contacts found take over the slots they continue (match_slots). The point's slots
// start at `first` of slot and hist; prev and prev_hist: the slots as they were (n_prev of them),
// taken: which of them go on.
inline void carry_slots(MeshSlot* slot, const ContactHistories& hist, std::size_t first, std::size_t n_prev, Found* found,
                 std::size_t nf, MeshSlot* prev, ContactHistory* prev_hist, bool* taken) {
  match_slots(slot, n_prev, found, nf, taken);
  std::copy(slot, slot + n_prev, prev);
  for (std::size_t k = 0; k < n_prev; ++k) prev_hist[k] = hist.get(first + k);
}

// Step 3's start: slot f, at `at` in hist, continues its contact's history (or starts afresh) at
// the contact found.
inline MeshSlot& renew_slot(MeshSlot* slot, ContactHistories& hist, std::size_t at, std::size_t f, const Found& fd,
                     const MeshSlot* prev, const ContactHistory* prev_hist) {
  MeshSlot& s = slot[f];
  s = fd.from >= 0 ? prev[fd.from] : MeshSlot{};
  hist.set(at, fd.from >= 0 ? prev_hist[fd.from] : ContactHistory{});
  s.surface = fd.surface;
  s.key = fd.hit.key;
  s.n = fd.n;
  s.overlap = fd.overlap;
  return s;
}

}  // namespace bagdem::surface_contacts
