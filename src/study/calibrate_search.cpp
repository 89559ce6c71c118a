// The calibration's search on ensemble means (study/calibrate.hpp): roots of one target, the
// least-squares value of several.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "bagdem/study/calibrate.hpp"

namespace bagdem::study {

bool search_in_log(double lo, double hi) { return lo > 0 && hi > 0 && hi >= 3 * lo; }

double allowance(const Estimate& e, double tolerance) { return std::isfinite(e.ci95) ? std::max(e.ci95, tolerance) : tolerance; }

namespace {

// The evaluations so far, with the search coordinate u (log(value) or value) and the residuals.
class Evaluated {
 public:
  Evaluated(const std::vector<double>& targets, const SearchOptions& opt, const Evaluate& evaluate, SearchResult& out)
      : targets_(targets), opt_(opt), evaluate_(evaluate), out_(out) {}

  double u_of(double v) const { return opt_.log ? std::log(v) : v; }
  double v_of(double u) const { return opt_.log ? std::exp(u) : u; }

  // Runs the values not run before (one batch, in the order given); returns each one's index.
  std::vector<std::size_t> run(const std::vector<double>& values, int round) {
    std::vector<double> fresh;
    for (double v : values)
      if (find(v) == npos && std::find(fresh.begin(), fresh.end(), v) == fresh.end()) fresh.push_back(v);
    if (!fresh.empty()) {
      const auto est = evaluate_(fresh);
      if (est.size() != fresh.size()) throw std::logic_error("calibrate_search: the evaluator returned a wrong count");
      for (std::size_t i = 0; i < fresh.size(); ++i) {
        if (est[i].size() != targets_.size()) throw std::logic_error("calibrate_search: an evaluation lacks a target");
        out_.evaluated.push_back({fresh[i], round, est[i]});
      }
    }
    std::vector<std::size_t> at;
    for (double v : values) at.push_back(find(v));
    return at;
  }
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);
  std::size_t size() const { return out_.evaluated.size(); }
  std::size_t find(double v) const {
    for (std::size_t i = 0; i < out_.evaluated.size(); ++i)
      if (out_.evaluated[i].value == v) return i;
    return npos;
  }
  const Evaluation& operator[](std::size_t i) const { return out_.evaluated[i]; }

  double residual(std::size_t i, std::size_t k) const { return out_.evaluated[i].at[k].mean - targets_[k]; }
  // The target's allowance at i: its interval, at least the tolerance.
  double allowance(std::size_t i, std::size_t k) const { return study::allowance(out_.evaluated[i].at[k], opt_.tolerance); }
  bool matched(std::size_t i) const {
    for (std::size_t k = 0; k < targets_.size(); ++k)
      if (!(std::abs(residual(i, k)) <= allowance(i, k))) return false;
    return true;
  }
  double cost(std::size_t i) const {
    double J = 0;
    for (std::size_t k = 0; k < targets_.size(); ++k) J += residual(i, k) * residual(i, k);
    return std::isfinite(J) ? J : std::numeric_limits<double>::infinity();
  }

  // The solution at evaluated value i, with slopes from the evaluated values a (below) and b
  // (above) of it (npos: none on that side).
  Solution solution(std::size_t i, std::size_t a, std::size_t b) const {
    Solution s;
    s.value = out_.evaluated[i].value;
    s.at = out_.evaluated[i].at;
    s.matched = matched(i);
    const std::size_t lo = a != npos ? a : i, hi = b != npos ? b : i;
    double num = 0, den = 0, step = 0;
    for (std::size_t k = 0; k < targets_.size(); ++k) {
      s.residual.push_back(residual(i, k));
      const double dv = (*this)[hi].value - (*this)[lo].value;
      const double slope = lo != hi ? (residual(hi, k) - residual(lo, k)) / dv : NAN;
      s.slope.push_back(slope);
      const double w = allowance(i, k);
      num += slope * slope * w * w;
      den += slope * slope;
      step += slope * s.residual.back();
    }
    const bool sloped = den > 0 && std::isfinite(den) && std::isfinite(step);
    s.spread = sloped ? std::sqrt(num) / den : std::numeric_limits<double>::infinity();
    s.half_width = sloped ? std::abs(step) / den + s.spread : std::numeric_limits<double>::infinity();
    return s;
  }

  // The evaluated values in ascending order of value.
  std::vector<std::size_t> sorted() const {
    std::vector<std::size_t> idx(out_.evaluated.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](std::size_t x, std::size_t y) { return out_.evaluated[x].value < out_.evaluated[y].value; });
    return idx;
  }

 private:
  const std::vector<double>& targets_;
  const SearchOptions& opt_;
  const Evaluate& evaluate_;
  SearchResult& out_;
};

std::string text(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

// One target: the roots bracketed by the scan, each refined by safeguarded regula falsi.
namespace {

// A change of sign of the residual between two evaluated values, narrowed round by round.
struct Bracket {
  std::size_t a, b;  // evaluated indices, value(a) < value(b), residuals of opposite signs
  bool open = true;
  std::size_t found = Evaluated::npos;
};

// Up to opt.rounds rounds: each open bracket asked at its secant point (kept within its middle
// 60%), and narrowed to the side of the sign change, or closed when its value matches or fails.
void refine_brackets(Evaluated& E, std::vector<Bracket>& brackets, const SearchOptions& opt) {
  for (int round = 1; round <= opt.rounds; ++round) {
    std::vector<double> ask;
    for (const Bracket& b : brackets) {
      if (!b.open) continue;
      const double ua = E.u_of(E[b.a].value), ub = E.u_of(E[b.b].value);
      const double ra = E.residual(b.a, 0), rb = E.residual(b.b, 0);
      const double w = ub - ua;
      const double u = std::clamp(ua - ra * w / (rb - ra), ua + 0.2 * w, ub - 0.2 * w);
      ask.push_back(E.v_of(u));
    }
    if (ask.empty()) break;
    const std::vector<std::size_t> got = E.run(ask, round);
    std::size_t q = 0;
    for (Bracket& b : brackets) {
      if (!b.open) continue;
      const std::size_t i = got[q++];
      const double r = E.residual(i, 0);
      if (E.matched(i)) {
        b.open = false, b.found = i;
      } else if (!std::isfinite(r)) {
        b.open = false;  // a failed value: the bracket ends here, unresolved
      } else if ((r < 0) == (E.residual(b.a, 0) < 0)) {
        b.a = i;
      } else {
        b.b = i;
      }
    }
  }
}

// The matched scan values, neighbours that all match taken as one solution: the best of them
// (least residual for its allowance), its half-width widened to cover them all, since the data
// cannot tell them apart.
void matched_scan_values(Evaluated& E, const std::vector<std::size_t>& scan, const std::vector<std::size_t>& hits, SearchResult& out,
                         std::ostringstream& note) {
  for (std::size_t first = 0; first < hits.size();) {
    std::size_t last = first;
    while (last + 1 < hits.size() && hits[last + 1] == hits[last] + 1) ++last;
    std::size_t best = hits[first];
    for (std::size_t k = first; k <= last; ++k)
      if (std::abs(E.residual(scan[hits[k]], 0)) / E.allowance(scan[hits[k]], 0) <
          std::abs(E.residual(scan[best], 0)) / E.allowance(scan[best], 0))
        best = hits[k];
    const std::size_t a = best > 0 ? scan[best - 1] : Evaluated::npos, b = best + 1 < scan.size() ? scan[best + 1] : Evaluated::npos;
    Solution s = E.solution(scan[best], a, b);
    if (last > first) {
      const double lo = E[scan[hits[first]]].value, hi = E[scan[hits[last]]].value;
      s.half_width = std::max({s.half_width, s.value - lo, hi - s.value});
      double widest = 0;
      for (std::size_t k = first; k <= last; ++k) widest = std::max(widest, E.allowance(scan[hits[k]], 0));
      note << "every value from " << text(lo) << " to " << text(hi) << " matches the target within its interval (up to +-" << text(widest)
           << " dB): the intervals, not the key, limit the answer there; more --seeds narrow them. ";
    }
    out.solutions.push_back(s);
    first = last + 1;
  }
}

// No solution: the closest value of the scan, reported as not matched; where it lies says what to
// change.
void closest_unmatched(Evaluated& E, const std::vector<std::size_t>& scan, const SearchOptions& opt, SearchResult& out,
                       std::ostringstream& note) {
  // The closest value of the scan, reported as not matched; where it lies says what to change.
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  std::size_t best = scan.size();
  for (std::size_t j = 0; j < scan.size(); ++j) {
    const double m = E[scan[j]].at[0].mean;
    if (!std::isfinite(m)) continue;
    lo = std::min(lo, m), hi = std::max(hi, m);
    if (best == scan.size() || std::abs(E.residual(scan[j], 0)) < std::abs(E.residual(scan[best], 0))) best = j;
  }
  note << "no value between " << text(opt.lo) << " and " << text(opt.hi) << " reaches the target: the reduction runs from "
       << text(lo) << " to " << text(hi) << " dB over the scan";
  if (best == scan.size()) {
    note << ". ";
  } else {
    out.solutions.push_back(E.solution(scan[best], best > 0 ? scan[best - 1] : Evaluated::npos,
                                       best + 1 < scan.size() ? scan[best + 1] : Evaluated::npos));
    if (best == 0 || best + 1 == scan.size())
      note << ", nearest at the bound " << text(E[scan[best]].value) << ": widen --bounds. ";
    else
      note << ", nearest at " << text(E[scan[best]].value) << " inside the bounds: a wider range will not reach it; another key sets it "
           << "(the structure's damping, say). ";
  }
}

}  // namespace

void roots(Evaluated& E, const std::vector<std::size_t>& scan, const SearchOptions& opt, SearchResult& out) {
  std::vector<Bracket> brackets;
  std::vector<std::size_t> hits;  // scan values that match, each a solution
  for (std::size_t j = 0; j < scan.size(); ++j) {
    const std::size_t i = scan[j];
    if (E.matched(i)) {
      hits.push_back(j);
      continue;
    }
    if (j + 1 < scan.size()) {
      const std::size_t n = scan[j + 1];
      const double r0 = E.residual(i, 0), r1 = E.residual(n, 0);
      if (std::isfinite(r0) && std::isfinite(r1) && !E.matched(n) && (r0 < 0) != (r1 < 0)) brackets.push_back({i, n});
    }
  }
  refine_brackets(E, brackets, opt);
  // Solutions: the matched scan values (neighbours of the scan for the slope), the brackets'
  // matched values (their ends), and the unresolved brackets' nearer end, not matched.
  std::ostringstream note;
  matched_scan_values(E, scan, hits, out, note);
  for (const Bracket& b : brackets) {
    if (b.found != Evaluated::npos) {
      out.solutions.push_back(E.solution(b.found, b.a, b.b));
    } else {
      const std::size_t nearer = std::abs(E.residual(b.a, 0)) <= std::abs(E.residual(b.b, 0)) ? b.a : b.b;
      out.solutions.push_back(E.solution(nearer, b.a, b.b));
      note << "the root between " << text(E[b.a].value) << " and " << text(E[b.b].value) << " was not matched in "
           << opt.rounds << " rounds (give --rounds, --seeds or --tolerance). ";
    }
  }
  if (out.solutions.empty()) closest_unmatched(E, scan, opt, out, note);
  out.note = note.str();
}

// Several targets: the least-squares value, by halving the spacing around the best.
void least_squares(Evaluated& E, const std::vector<std::size_t>& scan, const SearchOptions& opt, SearchResult& out) {
  std::size_t best = scan[0];
  for (std::size_t i : scan)
    if (E.cost(i) < E.cost(best)) best = i;
  std::ostringstream note;
  for (std::size_t j = 1; j + 1 < scan.size(); ++j)
    if (scan[j] != best && E.cost(scan[j]) < E.cost(scan[j - 1]) && E.cost(scan[j]) < E.cost(scan[j + 1]))
      note << "the sum of squares has another minimum near " << text(E[scan[j]].value) << ". ";
  if (!std::isfinite(E.cost(best))) {
    out.note = note.str() + "no value of the scan gave every target a figure. ";
    return;
  }
  double h = E.u_of(E[scan[1]].value) - E.u_of(E[scan[0]].value);
  auto neighbours = [&](std::size_t i) {
    std::size_t a = Evaluated::npos, b = Evaluated::npos;
    for (std::size_t j : E.sorted()) {
      if (E[j].value < E[i].value) a = j;
      if (E[j].value > E[i].value && b == Evaluated::npos) b = j;
    }
    return std::pair{a, b};
  };
  for (int round = 1; round <= opt.rounds; ++round) {
    // Stop once the spacing is below the value's own uncertainty: finer steps cannot be told apart.
    const auto [a, b] = neighbours(best);
    const Solution s = E.solution(best, a, b);
    const double u = E.u_of(E[best].value);
    if (std::isfinite(s.spread) && std::abs(E.v_of(u + 0.5 * h) - E[best].value) < s.spread) break;
    std::vector<double> ask;
    for (double side : {-0.5, 0.5}) {
      const double uv = u + side * h;
      if (uv >= E.u_of(opt.lo) - 1e-12 * std::abs(uv) && uv <= E.u_of(opt.hi) + 1e-12 * std::abs(uv)) ask.push_back(E.v_of(uv));
    }
    for (std::size_t i : E.run(ask, round))
      if (E.cost(i) < E.cost(best)) best = i;
    h *= 0.5;
  }
  // A least-squares value that leaves a target outside its interval gives way to the matched value
  // of least squares among those run, if any: matching every target is what calibrating means.
  if (!E.matched(best)) {
    std::size_t chosen = Evaluated::npos;
    for (std::size_t i = 0; i < E.size(); ++i)
      if (E.matched(i) && (chosen == Evaluated::npos || E.cost(i) < E.cost(chosen))) chosen = i;
    if (chosen != Evaluated::npos) {
      note << "the least-squares value " << text(E[best].value) << " leaves a target outside its interval; "
           << text(E[chosen].value) << " matches every target. ";
      best = chosen;
    }
  }
  const auto [a, b] = neighbours(best);
  out.solutions.push_back(E.solution(best, a, b));
  out.note = note.str();
}

}  // namespace

SearchResult calibrate_search(const std::vector<double>& targets, const SearchOptions& opt, const Evaluate& evaluate) {
  if (targets.empty()) throw std::invalid_argument("calibrate_search: no target");
  if (!(opt.lo < opt.hi)) throw std::invalid_argument("calibrate_search: the bounds must satisfy lo < hi");
  if (opt.scan < 3) throw std::invalid_argument("calibrate_search: the scan needs at least 3 values");
  if (opt.log && !(opt.lo > 0)) throw std::invalid_argument("calibrate_search: a log scan needs positive bounds");
  SearchResult out;
  Evaluated E(targets, opt, evaluate, out);
  std::vector<double> values;
  const double u0 = E.u_of(opt.lo), u1 = E.u_of(opt.hi);
  for (int i = 0; i < opt.scan; ++i)
    values.push_back(i == 0 ? opt.lo : i == opt.scan - 1 ? opt.hi : E.v_of(u0 + (u1 - u0) * i / (opt.scan - 1)));
  const std::vector<std::size_t> scan = E.run(values, 0);
  if (targets.size() == 1) roots(E, scan, opt, out);
  else least_squares(E, scan, opt, out);
  std::sort(out.solutions.begin(), out.solutions.end(), [](const Solution& a, const Solution& b) { return a.value < b.value; });
  return out;
}

}  // namespace bagdem::study
