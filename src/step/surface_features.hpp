// The triangles stage's contact finding (surfaces.cpp): the terms of a ball's or a film node's
// elastic energy against a triangulated surface (euler_terms), the contacts of the law (one per
// patch, joined: PatchBlend), and the slots whose histories they continue.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "bagdem/contact/law.hpp"
#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/neighbour/mesh_candidates.hpp"
#include "history.hpp"
#include "mesh_slot.hpp"

namespace bagdem::surface_contacts {

// A hit joined into a patch's contact (PatchBlend): where it touches, its own normal, and its share
// of the law's force and of the contact point's velocity and mobility.
struct PatchMember {
  std::uint32_t triangle;
  Vec3 weights, point, n;
  double share;
};

// A contact of the law found this step (damping and friction; the elastic force is euler_terms'):
// the feature hit (a patch's deepest), the normal towards the body, the overlap, and the slot of
// the previous step whose history it continues (-1: new). A contact joining several hits of a patch
// (members > 1) has the joined normal and overlap and each hit in `member`, deepest first.
struct Found {
  std::uint32_t surface;
  MeshHit hit;
  Vec3 n;
  double overlap;
  int from;
  std::uint8_t members = 1;
  PatchMember member[kPatchMembers];  // the first `members` when members > 1 (else unset)
};

// The angle-weighted pseudonormal of the hit's feature (Baerentzen & Aanaes, "Signed distance
// computation using the angle weighted pseudonormal", IEEE TVCG 11(3), 2005, eq. 4): a face's
// normal; an edge's, the sum of its one or two faces' unit normals (each seen under the angle pi);
// a vertex's, the sum of its faces' unit normals, each weighted by the face's angle there. Not
// normalized: only its sign against a direction is asked.
inline Vec3 pseudonormal(const TriangleMesh& mesh, const std::vector<Vec3>& vx, const MeshHit& mh) {
  auto face = [&](std::uint32_t t) {
    const auto& tri = mesh.triangles[t];
    return Vec3((vx[tri[1]] - vx[tri[0]]).cross(vx[tri[2]] - vx[tri[0]]).normalized());
  };
  const std::uint32_t index = mh.key & 0x3fffffffu;
  switch (mh.hit.feature) {
    case Feature::Face:
      return face(mh.triangle);
    case Feature::Edge: {
      const auto& et = mesh.edge_triangles[index];
      return et[1] == kNoTriangle ? face(et[0]) : Vec3(face(et[0]) + face(et[1]));
    }
    case Feature::Vertex:
      break;
  }
  Vec3 sum = Vec3::Zero();
  for (std::uint32_t k = mesh.vertex_triangle_begin[index]; k < mesh.vertex_triangle_begin[index + 1]; ++k) {
    const std::uint32_t t = mesh.vertex_triangles[k];
    const auto& tri = mesh.triangles[t];
    const int at = tri[0] == index ? 0 : tri[1] == index ? 1 : 2;
    const Vec3 a = vx[tri[(at + 1) % 3]] - vx[index], b = vx[tri[(at + 2) % 3]] - vx[index];
    sum += std::atan2(a.cross(b).norm(), a.dot(b)) * face(t);
  }
  return sum;
}

// Normal and overlap of a body at x on `side` of a surface (-1: against its triangles' normals),
// touching the hit's feature within `reach` (its key set: select_mesh_contacts). The side is judged
// by the feature's angle-weighted pseudonormal (pseudonormal): on a closed surface that does not
// cut itself, the sign of (x - closest point) . pseudonormal tells inside from outside at a face,
// an edge or a vertex alike (Baerentzen & Aanaes 2005, theorem 1), where the touched triangle's own
// normal misjudges a centre nearly in that triangle's plane beside a sharp fold. Returns false when
// the centre is beyond the mid-surface.
inline bool oriented(const Vec3& x, const std::vector<Vec3>& vx, const TriangleMesh& mesh, const MeshHit& mh, double side, double reach,
                     Vec3& n, double& overlap) {
  const Vec3 normal = pseudonormal(mesh, vx, mh);
  const Vec3 d = x - mh.hit.point;
  const double dist = std::sqrt(mh.hit.distance2);
  const bool own_side = side * d.dot(normal) >= 0;
  n = dist > 1e-12 * reach ? Vec3((own_side ? 1.0 : -1.0) * d / dist) : Vec3(side * normal.normalized());
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
      fd.n = c.blend.n, fd.overlap = c.blend.overlap;
      for (std::size_t j = 0; j < c.count; ++j) {
        const TriangleHit& h = hits[c.member[j]].hit.hit;
        fd.member[j] = {hits[c.member[j]].hit.triangle, h.weights, h.point, n[c.member[j]], c.blend.share[j]};
      }
    }
    kept.push_back(fd);
  }
  hits.assign(kept.begin(), kept.end());
}

// The elastic energy of a point (a ball, a film node) against a triangulated surface counts no
// contacts: it is the Euler characteristic's sum over the surface's features within reach,
//   U = sum over faces U_H(delta_f) - sum over interior edges U_H(delta_e) + sum over interior vertices U_H(delta_v),
// each delta the reach less the distance to the closed feature (its closest point), U_H the
// contact law's energy (Hertz's by default). Why: with A_t the part of the surface where the
// overlap exceeds t, a closed feature meets A_t exactly when its delta exceeds t, and those
// meetings are relatively open cells, so
// chi(A_t) = #faces - #edges + #vertices met (a surface's boundary edges and vertices are left out:
// they make chi of a half-disc 1); then U = integral of U_H'(t) chi(A_t) dt over t > 0. On a flat
// triangulation A_t is a disc and U = U_H(overlap) exactly, as against the plane; two contact
// regions count twice; and U is continuous (each term is) wherever contacts are born, split or
// merge, where any count of contacts jumps (docs/bag.md, Guards). It does not see a ring contact
// (an annulus has chi = 0; the ring's levels count nothing), which the film under a ball meets
// only where a node is pushed away from the ball inside its contact. Its gradient is each term's
// law's force along the term's normal, signed, on the point and (by the barycentric weights of
// the closest point) on the feature's nodes.
struct EulerTerm {
  Vec3 point, n;           // the feature's closest point; unit normal from it towards the point
  double overlap;          // reach - distance (unit: m)
  Vec3 weights;            // barycentric weights of the closest point on node[0..2] (0 where unused)
  std::uint32_t node[3];
  std::uint32_t surface;
  double sign;             // the signed number of terms carried (face +1, edge -1, vertex +1 each)
};

// A term's share of the energy and of the force on the point, by the law of its surface and the
// point (R_eff: the point's radius; contact/law.hpp, euler_share): U = sign U_law(delta) and
// F = -dU/dx = sign U_law'(delta) n (Hertz: U = sign c delta^(5/2), c = hertz_constant).
struct EulerLoad {
  double energy;
  Vec3 force;
};
inline EulerLoad euler_load(const EulerTerm& e, const PairLaw& law, double R_eff) {
  return visit_law(law.kind, [&](auto L) {
    const EulerShare s = decltype(L)::euler_share(law, R_eff, e.overlap, e.sign);
    return EulerLoad{s.energy, s.force * e.n};
  });
}

// The terms of point x (reach, in surface s's frame with vertices vx) from its triangles within
// reach (hits: their closest points), appended to out. Each term is carried by the lowest feature
// holding its closest point (a face's closest point on an edge is that edge's, an edge's at an end
// is that vertex's), whose distance is computed once, the same way for every term it carries (an
// edge from its lower vertex): the terms of one feature then cancel exactly, in integers, as the
// face's and the edge's of a flat triangulation do.
inline void euler_terms(const TriangleMesh& mesh, const std::vector<Vec3>& vx, const Vec3& x, double reach, double side,
                        const std::vector<MeshHit>& hits, std::uint32_t s, std::vector<EulerTerm>& out) {
  struct Carrier {
    std::uint32_t key;  // feature_key
    int count;          // the signed number of terms it carries
    std::uint32_t triangle;  // one of its triangles (the side of a crossing)
  };
  thread_local std::vector<Carrier> carriers;
  thread_local std::vector<std::uint32_t> seen;  // edges and vertices looked at (feature keys)
  carriers.clear(), seen.clear();
  auto carry = [&](std::uint32_t key, int sign, std::uint32_t t) {
    for (Carrier& c : carriers)
      if (c.key == key) return void(c.count += sign);
    carriers.push_back({key, sign, t});
  };
  // An edge's closest point from its lower vertex: the parameter t along it.
  auto along = [&](std::uint32_t e) {
    const Vec3 &a = vx[mesh.edge_vertices[e][0]], &b = vx[mesh.edge_vertices[e][1]];
    const Vec3 E = b - a;
    return (x - a).dot(E) / E.squaredNorm();
  };
  // The carrier of a closest point on edge e: the edge, or the end the point is at.
  auto on_edge = [&](std::uint32_t e) {
    const double t = along(e);
    return t <= 0 ? feature_key(Feature::Vertex, mesh.edge_vertices[e][0])
           : t >= 1 ? feature_key(Feature::Vertex, mesh.edge_vertices[e][1])
                    : feature_key(Feature::Edge, e);
  };
  const double reach2 = reach * reach;
  for (const MeshHit& mh : hits) {
    const auto& tri = mesh.triangles[mh.triangle];
    const TriangleHit& h = mh.hit;
    // The face's term.
    if (h.feature == Feature::Face) carry(feature_key(Feature::Face, mh.triangle), 1, mh.triangle);
    else if (h.feature == Feature::Edge) carry(on_edge(mesh.triangle_edges[mh.triangle][h.local]), 1, mh.triangle);
    else carry(feature_key(Feature::Vertex, tri[h.local]), 1, mh.triangle);
    // Its interior edges' and vertices' terms, once each.
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t e = mesh.triangle_edges[mh.triangle][k];
      if (mesh.edge_triangles[e][1] == kNoTriangle) continue;  // a boundary edge
      const std::uint32_t key = feature_key(Feature::Edge, e);
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
      seen.push_back(key);
      const double t = std::clamp(along(e), 0.0, 1.0);
      const Vec3 &a = vx[mesh.edge_vertices[e][0]], &b = vx[mesh.edge_vertices[e][1]];
      if ((x - (a + t * (b - a))).squaredNorm() < reach2) carry(on_edge(e), -1, mh.triangle);
    }
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t v = tri[k], key = feature_key(Feature::Vertex, v);
      if (mesh.vertex_on_boundary[v] || std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
      seen.push_back(key);
      if ((x - vx[v]).squaredNorm() < reach2) carry(key, 1, mh.triangle);
    }
  }
  for (const Carrier& c : carriers) {
    if (c.count == 0) continue;
    const std::uint32_t index = c.key & 0x3fffffffu;
    EulerTerm term;
    term.surface = s;
    term.sign = c.count;
    term.weights = Vec3::Zero();
    switch (static_cast<Feature>(c.key >> 30)) {
      case Feature::Face: {
        const auto& tri = mesh.triangles[index];
        const TriangleHit h = closest_point_on_triangle(x, vx[tri[0]], vx[tri[1]], vx[tri[2]]);
        term.point = h.point, term.weights = h.weights;
        term.node[0] = tri[0], term.node[1] = tri[1], term.node[2] = tri[2];
        break;
      }
      case Feature::Edge: {
        const std::uint32_t a = mesh.edge_vertices[index][0], b = mesh.edge_vertices[index][1];
        const double t = along(index);
        term.point = vx[a] + t * (vx[b] - vx[a]);
        term.weights = Vec3(1 - t, t, 0);
        term.node[0] = a, term.node[1] = b, term.node[2] = a;
        break;
      }
      case Feature::Vertex:
        term.point = vx[index];
        term.weights = Vec3(1, 0, 0);
        term.node[0] = term.node[1] = term.node[2] = index;
        break;
    }
    const double d = (x - term.point).norm();
    term.overlap = reach - d;
    if (term.overlap <= 0) continue;  // rounding at the reach
    if (d > 1e-12 * reach) {
      term.n = (x - term.point) / d;
    } else {  // on the surface: a crossing, which stops the run
      const auto& tri = mesh.triangles[c.triangle];
      term.n = side * (vx[tri[1]] - vx[tri[0]]).cross(vx[tri[2]] - vx[tri[0]]).normalized();
    }
    out.push_back(term);
  }
}

// The overlap each contact's law sees (out[f] for found[f]): the one whose stiffness is the Euler
// sum's along the contact's normal, sum over its terms of sign S(delta) (n_term . n)^2, so that the
// law's damping gives the requested restitution and its friction the matching normal force (Hertz:
// S = 2 E* sqrt(R* delta), the overlap the square of the sum of sign sqrt(delta) cos^2; a linear
// spring: the sum of sign delta cos; the law's overlap_term and overlap_of). A term goes to the
// contact of its surface whose normal is closest to its own. On a flat triangulation it is the
// contact's own overlap; where the sum is not positive (a ring contact), 1e-12 of it.
// law_of(s): the law of surface s and the point.
template <class LawOf>
void law_overlaps(const std::vector<EulerTerm>& terms, const Found* found, std::size_t nf, LawOf&& law_of, double* out) {
  for (std::size_t f = 0; f < nf; ++f) out[f] = 0;
  for (const EulerTerm& e : terms) {
    std::size_t best = nf;
    double c_best = -2;
    for (std::size_t f = 0; f < nf; ++f) {
      if (found[f].surface != e.surface) continue;
      const double c = e.n.dot(found[f].n);
      if (c > c_best) c_best = c, best = f;
    }
    if (best < nf)
      out[best] += visit_law(law_of(e.surface).kind, [&](auto L) { return decltype(L)::overlap_term(e.sign, e.overlap, c_best); });
  }
  for (std::size_t f = 0; f < nf; ++f)
    out[f] = out[f] > 0 ? visit_law(law_of(found[f].surface).kind, [&](auto L) { return decltype(L)::overlap_of(out[f]); })
                        : 1e-12 * found[f].overlap;
}

// The point `i` of a surface contact (a ball, or a film node) against the triangulated surfaces:
// where it is in surface s's frame, the vertices there, its reach and its side (-1: against the
// triangles' normals); closed: the surface is closed and keeps its layers apart (the bag's film with
// film-film contact), so that the point's side of it as a whole is its winding number's.
struct PointView {
  Vec3 x;
  const std::vector<Vec3>* vertices;
  double reach, side;
  bool closed = false;
};

// Step 1 of a point's surface contacts, one feature finder for balls and film nodes: the features
// it touches now. The closest points of its candidate triangles (cand[s], entries of point i)
// within reach give the elastic energy's terms (euler_terms, into terms), and, one per feature
// (select_mesh_contacts), oriented, one per patch (keep_patches), the contacts whose damping and
// friction the law gives; at most kMax into found, in surface order. view(s) places the point (PointView); touched(s,
// overlap, reach, own_side) sees each contact found (own_side false: the point is beyond the mid-surface, by its
// nearest hit; a farther hit seen from its outer side is dropped); full() is told when one did not fit.
// gap (when not null): the least distance of a candidate beyond the point's reach (HUGE_VAL
// without candidates), rounded down.
template <std::size_t kMax, class Surfaces, class View, class Touched, class Full>
inline std::size_t find_features(const Surfaces& surfaces, const std::vector<MeshCandidates>& cand, std::size_t i,
                          const View& view, const Touched& touched, const Full& full, Found* found,
                          std::vector<EulerTerm>& terms, double* gap = nullptr) {
  thread_local std::vector<MeshHit> hits;
  thread_local std::vector<Found> patch;
  std::size_t nf = 0;
  terms.clear();
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
    euler_terms(mesh, vx, pv.x, pv.reach, pv.side, hits, s, terms);
    select_mesh_contacts(mesh, hits);
    // The point's side of the surface is its nearest hit's (oriented; the nearest always survives
    // select_mesh_contacts). Another hit seen from its outer side lies behind a nearer part of the
    // surface (a point on the inner side sees only inner sides unless the surface is between:
    // a film doubled in a pleat, closer than the reach): no contact of the law, not a crossing.
    std::size_t nearest = 0;
    for (std::size_t k = 1; k < hits.size(); ++k)
      if (hits[k].hit.distance2 < hits[nearest].hit.distance2) nearest = k;
    patch.clear();
    for (std::size_t k = 0; k < hits.size(); ++k) {
      const MeshHit& mh = hits[k];
      Vec3 n;
      double overlap;
      bool own_side = oriented(pv.x, vx, mesh, mh, pv.side, pv.reach, n, overlap);
      if (!own_side && k != nearest) continue;
      // The nearest hit seen from its outer side: a crossing, unless the point is on its own side of
      // the closed film as a whole (its winding number). A film crushed against a wall can pass
      // through itself locally for a moment, a sliver triangle slipping between the film-film
      // contact's node spheres, and turn a flap's outer side to a ball that is inside; the ball then
      // touches that flap from the side it is on, as the Euler sum's elastic force already has it.
      // Without film-film contact (closed false) the film may tangle for good: a crossing, as before.
      if (!own_side && pv.closed && (winding_number(mesh, vx, pv.x) > 0.5) == (pv.side < 0))
        own_side = oriented(pv.x, vx, mesh, mh, -pv.side, pv.reach, n, overlap);
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
