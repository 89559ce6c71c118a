// The drop test where a run has no other restitution (run/drop_fallback.hpp).
#include "bagdem/run/drop_fallback.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bagdem/error.hpp"
#include "bagdem/run/drop_test.hpp"

namespace bagdem {

std::string drop_where_no_restitution(const Scene& scene, std::vector<ReducedRow>& rows, const std::filesystem::path& out_dir,
                                      bool quiet) {
  if (std::none_of(rows.begin(), rows.end(), [](const ReducedRow& r) { return r.e_method == "none"; })) return "";
  DropResult d;
  try {
    d = run_drop_test(scene, 0.0, out_dir, quiet);
  } catch (const InputError& e) {
    return e.what();
  } catch (const RunError& e) {
    return e.what();
  }
  write_drop_result(out_dir / "drop_result.csv", d, scene);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  for (ReducedRow& r : rows) {
    r.e_drop = d.restitution;
    if (r.e_method == "none") choose_restitution(r, Interval{.mean = kNaN, .se = kNaN, .ci95 = kNaN});
  }
  return "";
}

}  // namespace bagdem
