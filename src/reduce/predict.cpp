// Prediction from an effective-field map (reduce/predict.hpp).
#include "bagdem/reduce/predict.hpp"

#include "bagdem/reduce/map_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <tuple>

#include "bagdem/error.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/structure/response.hpp"

namespace bagdem {
namespace fs = std::filesystem;

namespace {

// The interval [k, k + 1] of an ascending grid holding x (its last interval at the top end).
std::size_t bracket(const std::vector<double>& grid, double x) {
  const auto it = std::upper_bound(grid.begin(), grid.end(), x);
  const std::size_t k = static_cast<std::size_t>(it - grid.begin());
  return std::min(k == 0 ? 0 : k - 1, grid.size() - 2);
}

}  // namespace

std::optional<std::pair<double, double>> EffectiveMap::at(double X, double f, int m_sign, int c_sign) const {
  if (gamma.size() < 2 || frequency.size() < 2 || !(X > 0)) return std::nullopt;
  if (!covers(f)) return std::nullopt;
  f = std::clamp(f, frequency.front(), frequency.back());
  const double G = gamma_of(X, f);
  if (G < gamma.front() || G > gamma.back()) return std::nullopt;
  const std::size_t i = bracket(gamma, G), j = bracket(frequency, f), nf = frequency.size();
  const double s = std::log(G / gamma[i]) / std::log(gamma[i + 1] / gamma[i]);
  const double t = (f - frequency[j]) / (frequency[j + 1] - frequency[j]);
  double m = 0, c = 0;
  for (int di = 0; di < 2; ++di)
    for (int dj = 0; dj < 2; ++dj) {
      const std::size_t k = (i + di) * nf + j + dj;
      const double weight = (di ? s : 1 - s) * (dj ? t : 1 - t);
      // A corner of the interval needs the cell's interval (NaN with one start: not known).
      const double mk = M_eff[k] + (m_sign != 0 ? m_sign * M_eff_ci95[k] : 0.0), ck = C_eff[k] + (c_sign != 0 ? c_sign * C_eff_ci95[k] : 0.0);
      if (!std::isfinite(mk) || !std::isfinite(ck)) return std::nullopt;
      m += weight * mk, c += weight * ck;
    }
  return std::make_pair(m, c);
}

bool EffectiveMap::covers(double f) const {
  const double tol = 1e-8 * frequency.back();  // the map's grid and a sweep's band, each rounded to its digits
  if (!(f >= frequency.front() - tol && f <= frequency.back() + tol)) return false;
  if (!bands.empty())
    return std::any_of(bands.begin(), bands.end(), [&](const auto& b) { return f >= b.first - tol && f <= b.second + tol; });
  const std::size_t j = bracket(frequency, std::clamp(f, frequency.front(), frequency.back()));
  if (f <= frequency[j] + tol || f >= frequency[j + 1] - tol) return true;  // on a line
  return !band_gap(j);
}

// Each band of characterize has its frequencies evenly spaced; the lines of two bands are parted by
// a gap wider than the spacing on either side of it (a band of two lines: its width). A gap no
// wider than a neighbouring spacing is interpolated like it.
bool EffectiveMap::band_gap(std::size_t j) const {
  const double g = frequency[j + 1] - frequency[j];
  double beside = 0;
  if (j > 0) beside = std::max(beside, frequency[j] - frequency[j - 1]);
  if (j + 2 < frequency.size()) beside = std::max(beside, frequency[j + 2] - frequency[j + 1]);
  return beside > 0 && g > (1 + 1e-3) * beside;
}

namespace {

// |f''| h^2 / 8 at every line of an axis for one cell row (values v at coordinates x), the largest
// of the line's and its neighbours' (a point between two lines is read from both); the lines
// parted into bands by gaps over 3 times the median spacing when `bands`; NaN in a band of fewer
// than 3 lines or next to a NaN value. The curvature the values' own scatter could make (their 95%
// half-widths ci through the second difference, the cells independent) is not the map's shape and
// is taken off: noise is the interval's business, not the interpolation's.
std::vector<double> curvature_bounds(const std::vector<double>& x, const std::vector<double>& v, const std::vector<double>& ci, bool bands) {
  const std::size_t n = x.size();
  std::vector<double> out(n, NAN), gaps;
  for (std::size_t k = 1; k < n; ++k) gaps.push_back(x[k] - x[k - 1]);
  double median = INFINITY;
  if (bands && !gaps.empty()) {
    std::vector<double> s = gaps;
    std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
    median = s[s.size() / 2];
  }
  for (std::size_t first = 0; first < n;) {
    std::size_t last = first;  // the band [first, last]
    while (last + 1 < n && !(gaps[last] > 3 * median)) ++last;
    if (last - first >= 2)
      for (std::size_t k = first; k <= last; ++k) {
        const std::size_t c = std::clamp(k, first + 1, last - 1);  // an end takes its inner neighbour's f''
        const double h0 = x[c] - x[c - 1], h1 = x[c + 1] - x[c];
        const double f2 = 2 * ((v[c + 1] - v[c]) / h1 - (v[c] - v[c - 1]) / h0) / (h0 + h1);
        const double noise = 2 / (h0 + h1) * std::hypot(ci[c + 1] / h1, ci[c] * (1 / h0 + 1 / h1), ci[c - 1] / h0);
        const double h = std::max(k > first ? x[k] - x[k - 1] : 0.0, k < last ? x[k + 1] - x[k] : 0.0);
        out[k] = std::max(0.0, std::abs(f2) - noise) * h * h / 8;  // NaN stays NaN
      }
    first = last + 1;
  }
  // A point between two lines is read from both: each line takes the larger bound of its cells'.
  std::vector<double> widest = out;
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t j : {k - 1, k + 1})
      if (j < n && !(k > 0 && j == k - 1 && bands && gaps[j] > 3 * median) && !(j == k + 1 && bands && gaps[k] > 3 * median))
        widest[k] = std::max(widest[k], out[j]);  // NaN stays NaN (std::max keeps its first argument)
  return widest;
}

}  // namespace

EffectiveMap EffectiveMap::interpolation_bounds() const {
  EffectiveMap b = *this;
  const auto scatter = [](double ci) { return std::isfinite(ci) ? ci : 0.0; };  // one start: no scatter to take off
  const std::size_t na = gamma.size(), nf = frequency.size();
  std::vector<double> log_gamma;
  for (double G : gamma) log_gamma.push_back(std::log(G));
  for (auto [value, ci, bound] : {std::tuple{&M_eff, &M_eff_ci95, &b.M_eff_ci95}, {&C_eff, &C_eff_ci95, &b.C_eff_ci95}}) {
    bound->assign(na * nf, 0.0);
    for (std::size_t j = 0; j < nf; ++j) {  // along Gamma, a column at a time
      std::vector<double> v, c;
      for (std::size_t i = 0; i < na; ++i) v.push_back((*value)[i * nf + j]), c.push_back(scatter((*ci)[i * nf + j]));
      const std::vector<double> e = curvature_bounds(log_gamma, v, c, false);
      for (std::size_t i = 0; i < na; ++i) (*bound)[i * nf + j] += e[i];
    }
    for (std::size_t i = 0; i < na; ++i) {  // along f, a row at a time
      const auto row = [&](const std::vector<double>* a) {
        return std::vector<double>(a->begin() + static_cast<long>(i * nf), a->begin() + static_cast<long>((i + 1) * nf));
      };
      std::vector<double> c = row(ci);
      for (double& x : c) x = scatter(x);
      const std::vector<double> e = curvature_bounds(frequency, row(value), c, true);
      for (std::size_t j = 0; j < nf; ++j) (*bound)[i * nf + j] += e[j];
    }
  }
  return b;
}

std::pair<double, double> EffectiveMap::amplitude_range(double f) const {
  return {amplitude_of(gamma.front(), f), amplitude_of(gamma.back(), f)};
}

EffectiveMap read_effective_map(const fs::path& path) {
  const std::vector<MapCell> cells = read_map_csv(path, {&MapCell::M_eff, &MapCell::C_eff});
  EffectiveMap m;
  m.source = path.string();
  std::vector<double> G, f;
  for (const MapCell& c : cells) {
    G.push_back(c.gamma), f.push_back(c.frequency);
    m.M_eff.push_back(c.M_eff.mean), m.M_eff_ci95.push_back(c.M_eff.ci95);
    m.C_eff.push_back(c.C_eff.mean), m.C_eff_ci95.push_back(c.C_eff.ci95);
  }
  for (double x : f)
    if (std::find(m.frequency.begin(), m.frequency.end(), x) == m.frequency.end()) m.frequency.push_back(x);
  for (double x : G)
    if (std::find(m.gamma.begin(), m.gamma.end(), x) == m.gamma.end()) m.gamma.push_back(x);
  const std::size_t na = m.gamma.size(), nf = m.frequency.size();
  bool grid = na >= 2 && nf >= 2 && G.size() == na * nf && std::is_sorted(m.gamma.begin(), m.gamma.end()) &&
              std::is_sorted(m.frequency.begin(), m.frequency.end());
  for (std::size_t k = 0; grid && k < G.size(); ++k) grid = G[k] == m.gamma[k / nf] && f[k] == m.frequency[k % nf];
  if (!grid)
    throw InputError(path.string(), "", "", "is not a grid of at least 2 Gamma x 2 frequencies, Gamma varying slowest (as bagdem characterize writes it)");
  // A cell's interval is NaN with one start: not known, so neither is a prediction's (at: its
  // corners have no figure there).
  return m;
}

FrequencyPrediction predict_at(const Primary& p, const EffectiveMap& map, double F, double f, int m_sign, int c_sign) {
  FrequencyPrediction out;
  out.frequency = f;
  if (!map.covers(f)) {
    out.outside = "band";
    return out;
  }
  const double w = 2 * std::numbers::pi * f;
  auto amplitudes = [&](double X) -> std::optional<Eigen::VectorXcd> {
    const auto mc = map.at(X, f, m_sign, c_sign);
    if (!mc) return std::nullopt;
    return p.steady_amplitudes(F, w, std::complex<double>(-w * w * mc->first, w * mc->second));
  };
  auto residual = [&](double X) -> std::optional<double> {
    const auto Q = amplitudes(X);
    if (!Q) return std::nullopt;
    return std::abs(p.at_cavity.cast<std::complex<double>>().dot(*Q)) / X - 1;  // relative: |U(X)| / X - 1
  };
  // The range of X, pulled in by a hair so that rounding keeps its ends inside the grid.
  auto [lo, hi] = map.amplitude_range(f);
  lo *= 1 + 1e-12, hi *= 1 - 1e-12;
  constexpr int kSamples = 160;
  std::vector<double> X(kSamples + 1);
  std::vector<std::optional<double>> r(kSamples + 1);
  bool any_positive = false, any_negative = false;
  for (int k = 0; k <= kSamples; ++k) {
    X[k] = lo * std::pow(hi / lo, double(k) / kSamples);
    r[k] = residual(X[k]);
    if (r[k]) (*r[k] > 0 ? any_positive : any_negative) = true;
  }
  for (int k = 0; k < kSamples; ++k) {
    if (!r[k] || !r[k + 1]) continue;
    double a = X[k], b = X[k + 1], ra = *r[k];
    if (ra == 0) b = a;
    else if ((ra > 0) == (*r[k + 1] > 0)) continue;
    for (int it = 0; it < 100 && b / a > 1 + 1e-14; ++it) {  // bisection in log X
      const double m = std::sqrt(a * b);
      const auto rm = residual(m);
      if (!rm) break;
      if ((*rm > 0) == (ra > 0)) a = m, ra = *rm;
      else b = m;
    }
    const double root = std::sqrt(a * b);
    if (const auto Q = amplitudes(root))
      out.solutions.push_back({root, std::abs(p.at_response.cast<std::complex<double>>().dot(*Q)), {}});
  }
  if (out.solutions.empty()) out.outside = any_positive && !any_negative ? "above" : any_negative && !any_positive ? "below" : "gap";
  return out;
}

std::vector<PredictedMode> predict_modes(const Primary& p, const EffectiveMap& map, double F, const std::vector<double>& frequencies,
                                         int points, Checks checks) {
  return predict_modes(p, std::vector<MappedDamper>{{&map, p.at_cavity, ""}}, F, frequencies, points, checks);
}

std::vector<PredictedMode> predict_modes(const Primary& p, const std::vector<MappedDamper>& dampers, double F,
                                         const std::vector<double>& frequencies, int points, Checks checks) {
  std::vector<PredictedMode> out;
  if (frequencies.empty()) return out;
  const auto [f_lo, f_hi] = std::minmax_element(frequencies.begin(), frequencies.end());
  auto bare = [&](double f) { return std::abs(p.bare_receptance(2 * std::numbers::pi * f)) * F; };
  for (std::size_t dof : p.evaluated_modes(*f_lo, *f_hi)) {
    PredictedMode m;
    m.mode = p.elastic_mode_number(dof);
    m.lo = INFINITY, m.hi = -INFINITY;
    for (double f : frequencies)
      if (p.nearest_elastic_mode(f) == dof) m.lo = std::min(m.lo, f), m.hi = std::max(m.hi, f);
    if (!(m.hi >= m.lo)) continue;
    const Peak b = bare_peak(p, m.lo, m.hi);  // as a sweep's (structure/response.hpp)
    m.bare_peak = b.magnitude * F, m.bare_frequency = b.frequency;
    // The damped peak at the map's means and at its interval's four corners.
    double corner_peak[5] = {};
    bool corner_left[5] = {};  // a corner that leaves the maps at any frequency has no peak over the band
    int peak_k = -1;  // where the means' peak lies among the frequencies
    const int signs[5][2] = {{0, 0}, {-1, -1}, {-1, 1}, {1, -1}, {1, 1}};
    std::vector<HarmonicSolution> last[5];  // several dampers: each corner's solutions at the frequency before
    for (int k = 0; k < points; ++k) {
      const double f = points > 1 ? m.lo + (m.hi - m.lo) * k / (points - 1) : m.lo;
      for (int c = 0; c < (checks == Checks::none ? 1 : 5); ++c) {
        FrequencyPrediction fp = dampers.size() == 1 ? predict_at(p, *dampers[0].map, F, f, signs[c][0], signs[c][1])
                                                     : predict_at(p, dampers, F, f, signs[c][0], signs[c][1], &last[c]);
        last[c] = fp.solutions;
        if (!fp.outside.empty()) {
          corner_left[c] = true;
          if (c == 0) {
            if (m.outside.empty()) m.outside_why = fp.outside, m.outside_damper = fp.outside_damper;
            m.outside.push_back(f);
          }
          continue;
        }
        for (const HarmonicSolution& h : fp.solutions)
          if (h.response > corner_peak[c]) {
            corner_peak[c] = h.response;
            if (c == 0) {
              m.peak_frequency = f, peak_k = k;
              m.peak_cavity_gamma = h.cavity_amplitude * std::pow(2 * std::numbers::pi * f, 2) / dampers[0].map->g;
            }
          }
        if (c == 0) {
          m.points.push_back(std::move(fp));
          m.bare.push_back(bare(f));
        }
      }
    }
    m.peak = corner_peak[0];
    m.at_band_edge = points > 1 && (peak_k == 0 || peak_k == points - 1);  // as a sweep marks its peak (run/stepped_sine.hpp)
    auto db = [&](double peak) { return peak > 0 ? reduction_db(m.bare_peak, peak) : std::nan(""); };
    m.reduction_db = db(m.peak);
    m.reduction_db_lo = m.reduction_db_hi = m.reduction_db;
    for (int c = 1; c < 5; ++c) {
      const double r = db(corner_peak[c]);
      if (corner_left[c] || !std::isfinite(r)) continue;
      ++m.corners;
      m.reduction_db_lo = std::min(m.reduction_db_lo, r), m.reduction_db_hi = std::max(m.reduction_db_hi, r);
    }
    // The interval is the four corners' range; a corner that left the map leaves it unknown (not
    // the range of those left, which narrows as the map grows less certain).
    if (m.corners < 4) m.reduction_db_lo = m.reduction_db_hi = std::nan("");
    out.push_back(std::move(m));
  }
  if (checks != Checks::all) return out;
  // The resolution check: the interpolation's bounds to the four corners, as the interval's.
  std::vector<EffectiveMap> bounds;
  bounds.reserve(dampers.size());
  std::vector<MappedDamper> bounded = dampers;
  for (std::size_t k = 0; k < dampers.size(); ++k) bounded[k].map = &bounds.emplace_back(dampers[k].map->interpolation_bounds());
  for (const PredictedMode& b : predict_modes(p, bounded, F, frequencies, points, Checks::interval))
    for (PredictedMode& m : out)
      if (m.mode == b.mode && b.outside.empty() && b.corners == 4)
        m.interpolation_db = std::max(m.reduction_db - b.reduction_db_lo, b.reduction_db_hi - m.reduction_db);
  return out;
}

RandomPrediction predict_random(const Primary& p, const EffectiveMap& map, double rms, double lo, double hi, int lines, int m_sign,
                                int c_sign) {
  RandomPrediction out;
  std::vector<double> f(lines);
  for (int k = 0; k < lines; ++k) f[k] = lines > 1 ? lo + (hi - lo) * k / (lines - 1) : lo;
  for (double x : f)
    if (!map.covers(x)) {
      out.outside = "band";
      return out;
    }
  const double a = rms * std::sqrt(2.0 / lines);  // each line's force amplitude
  const Eigen::VectorXcd phi_b = p.at_cavity.cast<std::complex<double>>(), phi_a = p.at_response.cast<std::complex<double>>();
  // sigma_U and sigma_Y with the impedance read at amplitude A (A = 0: the bare structure).
  auto sigmas = [&](double A, double& su, double& sy) {
    double u2 = 0, y2 = 0;
    for (double x : f) {
      const double w = 2 * std::numbers::pi * x;
      std::complex<double> Z = 0;
      if (A > 0) {
        const auto mc = map.at(A, x, m_sign, c_sign);
        if (!mc) return false;
        Z = std::complex<double>(-w * w * mc->first, w * mc->second);
      }
      const Eigen::VectorXcd Q = p.steady_amplitudes(a, w, Z);
      u2 += 0.5 * std::norm(phi_b.dot(Q)), y2 += 0.5 * std::norm(phi_a.dot(Q));
    }
    su = std::sqrt(u2), sy = std::sqrt(y2);
    return true;
  };
  double su = 0, sy = 0;
  sigmas(0, su, sy);
  out.bare_response_rms = sy;
  double A = std::sqrt(2.0) * su;
  for (out.iterations = 1; out.iterations <= 500; ++out.iterations) {
    if (!sigmas(A, su, sy)) {
      out.outside = A < map.amplitude_range(lo).first ? "below" : "above";
      return out;
    }
    const double next = 0.5 * (A + std::sqrt(2.0) * su);
    const bool done = std::abs(next - A) <= 1e-10 * A;
    A = next;
    if (done) {
      out.converged = true;
      break;
    }
  }
  out.cavity_rms = su, out.response_rms = sy;
  return out;
}

RandomPredictionRange predict_random_range(const Primary& p, const EffectiveMap& map, double rms, double lo, double hi, int lines) {
  RandomPredictionRange r;
  r.mean = predict_random(p, map, rms, lo, hi, lines);
  r.response_rms_lo = r.response_rms_hi = r.mean.response_rms;
  if (!r.mean.outside.empty() || !r.mean.converged) return r;
  for (int m : {-1, 1})
    for (int c : {-1, 1}) {
      const RandomPrediction k = predict_random(p, map, rms, lo, hi, lines, m, c);
      if (k.outside.empty() && k.converged) {
        ++r.corners;
        r.response_rms_lo = std::min(r.response_rms_lo, k.response_rms), r.response_rms_hi = std::max(r.response_rms_hi, k.response_rms);
      }
    }
  if (r.corners < 4) r.response_rms_lo = r.response_rms_hi = std::nan("");  // as predict_modes' interval
  return r;
}

}  // namespace bagdem
