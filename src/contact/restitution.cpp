// See include/bagdem/contact/restitution.hpp for the model and its sources.
#include "bagdem/contact/restitution.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "bagdem/material.hpp"

namespace bagdem {

double tsuji_beta(double e) {
  const double le = std::log(e);
  return le / std::sqrt(le * le + std::numbers::pi * std::numbers::pi);
}

namespace {

// Dimensionless normal force of the impact x'' = -f(x, x'), clamped or not.
double force(double x, double xd, double a, bool clamped) {
  if (x <= 0) return 0.0;
  const double f = x * std::sqrt(x) + a * std::sqrt(std::sqrt(x)) * xd;
  return clamped ? std::max(0.0, f) : f;
}

}  // namespace

double restitution_of_damping(double a, bool clamped) {
  // State (x, v) with x(0) = 0, v(0) = 1. The undamped contact lasts 3.2 units; heavily damped ones
  // end earlier (they clamp). RK4 with h = 4e-5 gives e to better than 1e-7 (checked by halving).
  const double h = 4e-5;
  double x = 0, v = 1;
  for (int step = 0; step < 50'000'000; ++step) {
    auto acc = [&](double xx, double vv) { return -force(xx, vv, a, clamped); };
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v);
    const double xn = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double vn = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (xn <= 0) {
      // Left the contact within this step: interpolate the exit speed linearly in x.
      const double s = x / (x - xn);
      return std::max(0.0, -(v + s * (vn - v)));
    }
    if (clamped && vn < 0 && force(xn, vn, a, true) == 0.0) {
      // Clamped at zero while separating: from here on the force stays zero (x^(5/4) falls while
      // a x' stays), so the ball leaves with this speed.
      return -vn;
    }
    if (!clamped && vn < 0 && xn < 1e-300) return -vn;
    x = xn;
    v = vn;
    if (v >= 0 && x < 1e-14 && step > 100) return 0.0;  // stuck at the surface (infinite damping)
  }
  throw std::runtime_error("restitution_of_damping: no separation");
}

double clamped_beta(double e) {
  if (!restitution_in_range(e)) throw std::invalid_argument(std::string("clamped_beta: e must be in ") + kRestitutionRange);
  if (e == 1.0) return 0.0;
  // e(a) falls monotonically from 1 (a = 0) to 0 (a -> infinity). The root of e(exp(s)) - e in
  // s = log a, by regula falsi with the Illinois modification (the end kept twice has its value
  // halved), which keeps the bracket and converges superlinearly: 15-30 solutions of the
  // impact instead of bisection's 48, to a bracket of 1e-12 in log a.
  auto g = [e](double s) { return restitution_of_damping(std::exp(s), true) - e; };
  double lo = std::log(1e-8), hi = std::log(1e3);
  double g_lo = g(lo), g_hi = g(hi);  // > 0, < 0
  int kept = 0;                       // +1: lo kept last time, -1: hi kept
  for (int it = 0; it < 200 && hi - lo > 1e-12; ++it) {
    double s = lo - g_lo * (hi - lo) / (g_hi - g_lo);
    if (!(s > lo && s < hi)) s = 0.5 * (lo + hi);
    const double gs = g(s);
    if (gs == 0) return std::exp(s) / std::sqrt(5.0);
    if (gs > 0) {
      lo = s, g_lo = gs;
      if (kept == -1) g_hi *= 0.5;
      kept = -1;
    } else {
      hi = s, g_hi = gs;
      if (kept == +1) g_lo *= 0.5;
      kept = +1;
    }
  }
  return std::exp(0.5 * (lo + hi)) / std::sqrt(5.0);
}

}  // namespace bagdem
