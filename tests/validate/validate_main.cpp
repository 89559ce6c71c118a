// bagdem_validate: the heavier verification run by tools/validate (minutes, not part of tools/test).
// Full steel stiffness and wide sweeps of what the test suite checks on small scenes; prints one
// summary table and exits non-zero if any check is outside its tolerance.
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <vector>

#include "../impact.hpp"

using namespace bagdem;
using namespace bagdem::testing;

namespace {

struct Check {
  const char* what;
  double worst;
  double tolerance;
};

struct MaterialCase {
  const char* name;
  double rho, E, nu;
};

}  // namespace

int main() {
  const MaterialCase materials[] = {{"steel", 7800, 200e9, 0.3}, {"glass", 2500, 70e9, 0.22}, {"LDPE", 920, 0.25e9, 0.4}};
  const double speeds[] = {0.01, 0.03, 0.1, 0.3, 1, 3, 10};
  std::vector<Check> checks;

  // 1. Hertz impact, e = 1: duration and maximum overlap against Hertz theory (tolerance 1%).
  double worst_t = 0, worst_d = 0;
  for (const auto& m : materials)
    for (double v : speeds)
      for (bool wall : {false, true}) {
        const ImpactResult r = head_on_impact(m.rho, m.E, m.nu, 1.0, v, wall, 200);
        worst_t = std::max(worst_t, std::abs(r.duration / r.hertz_duration - 1));
        worst_d = std::max(worst_d, std::abs(r.max_overlap / r.hertz_overlap - 1));
      }
  checks.push_back({"Hertz contact duration, 3 materials x 7 speeds x pair/wall (rel. error)", worst_t, 0.01});
  checks.push_back({"Hertz maximum overlap, same sweep (rel. error)", worst_d, 0.01});

  // 2. Restitution 0.01 .. 0.99 (25 values) x 4 speeds x pair/wall, steel, 40 steps per contact;
  //    and its independence of the impact speed (Hertz + Tsuji damping: e depends on e alone).
  double worst_e = 0, worst_spread = 0;
  for (int k = 0; k < 25; ++k) {
    const double e = k == 0 ? 0.01 : k == 24 ? 0.99 : 0.04 * k;
    for (bool wall : {false, true}) {
      double lo = 1e300, hi = -1e300;
      for (double v : {0.01, 0.1, 1.0, 10.0}) {
        const ImpactResult r = head_on_impact(7800, 200e9, 0.3, e, v, wall, 40);
        worst_e = std::max(worst_e, std::abs(r.restitution / e - 1));
        lo = std::min(lo, r.restitution);
        hi = std::max(hi, r.restitution);
      }
      worst_spread = std::max(worst_spread, (hi - lo) / e);
    }
  }
  checks.push_back({"restitution 0.01-0.99 x 4 speeds x pair/wall, 40 steps/contact (rel. error)", worst_e, 0.01});
  // Each recovered e is within 1% (it varies with where in a step the contact opens), so two differ
  // by at most 2%.
  checks.push_back({"restitution spread over impact speeds 0.01-10 m/s (rel.)", worst_spread, 0.02});

  std::printf("| check | worst | tolerance | |\n|---|---|---|---|\n");
  bool ok = true;
  for (const auto& c : checks) {
    const bool pass = c.worst <= c.tolerance;
    ok = ok && pass;
    std::printf("| %s | %.3e | %.1e | %s |\n", c.what, c.worst, c.tolerance, pass ? "pass" : "FAIL");
  }
  std::printf("\n%d passed, %d failed\n", static_cast<int>(std::count_if(checks.begin(), checks.end(), [](const Check& c) { return c.worst <= c.tolerance; })),
              static_cast<int>(std::count_if(checks.begin(), checks.end(), [](const Check& c) { return c.worst > c.tolerance; })));
  return ok ? 0 : 1;
}
