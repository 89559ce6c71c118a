// The film's quadratic bending (bag/membrane.hpp, Bending; bag.film.bending_model = "quadratic"):
// per interior edge, W_b = k_e |s_e|^2 with s_e = sum_j w_j x_j over the edge's four nodes
// (x0, x1, xa, xb), the weights fixed by the rest shape. Used by membrane.cpp only.
//
// Bergou, Wardetzky, Harmon, Zorin & Grinspun, "A quadratic bending model for inextensible
// surfaces", Eurographics SGP 2006: for isometric deformations of a flat sheet the discrete bending
// energy is quadratic in the positions, W = x^T Q x / 2, with Q constant. Here each edge's stencil
// is the one vector w with sum w_j = 0 and sum w_j p_j = 0 for the hinge unfolded flat (p_j its
// nodes in the plane, a and b on either side of the edge): w_a = 1 / h_a, w_b = 1 / h_b (h: a
// wing's height over the edge), and the edge's nodes the rest, split by where the wings project on
// it (s = (x_w - x0) . e / |e|^2). So s_e vanishes on any flat placement of the hinge (a flat
// sheet moved rigidly or stretched in its plane bends nothing), and for wings folded rigidly by
// theta about the edge |s_e| = 2 sin(theta / 2): at small angles k_e theta^2, the hinge law's energy
// about a flat rest (hinge.hpp), with the same k_e; bounded as a fold grows.
// What it changes: the rest shape is flat (a bag made of flat film), so a curved rest shape holds a
// small bending stress; and the force is linear in the positions, so its stiffness is constant
// (no angle, no normal, no division at run time): a wing collapsing to a line stiffens nothing, and
// the highest frequency at rest bounds it for every shape.
#pragma once
#include <array>
#include <cmath>

#include "bagdem/vec3.hpp"

namespace bagdem::quadratic_bending {

// The stencil weights of the hinge (x0, x1, xa, xb) unfolded flat, from its rest positions.
inline std::array<double, 4> weights(const Vec3& x0, const Vec3& x1, const Vec3& xa, const Vec3& xb) {
  const Vec3 e = x1 - x0;
  const double le2 = e.squaredNorm(), le = std::sqrt(le2);
  const double wa = le / e.cross(xa - x0).norm(), wb = le / e.cross(xb - x0).norm();  // 1 / h
  const double sa = (xa - x0).dot(e) / le2, sb = (xb - x0).dot(e) / le2;
  return {-(wa * (1.0 - sa) + wb * (1.0 - sb)), -(wa * sa + wb * sb), wa, wb};
}

// s_e at positions (x0, x1, xa, xb).
inline Vec3 curvature(const std::array<double, 4>& w, const Vec3& x0, const Vec3& x1, const Vec3& xa, const Vec3& xb) {
  return w[0] * x0 + w[1] * x1 + w[2] * xa + w[3] * xb;
}

}  // namespace bagdem::quadratic_bending
