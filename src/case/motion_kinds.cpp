// [cavity.motion] kinds. The table below is the only list.
//   fixed      (no keys)
//   harmonic   amplitude (m), frequency (Hz), direction [x, y, z] (default x), phase (rad, default 0)
//   table      file = CSV with header and columns t, x, y, z (SI)
// Every kind but fixed also takes ramp (s, default 0 = none): a smooth start over that time
// (make_ramped_motion), instead of starting the motion at once after settling.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bagdem/case/load_case.hpp"

namespace bagdem {
namespace {

std::unique_ptr<Motion> fixed(const CaseReader&, const Scene&) { return make_fixed_motion(); }

std::unique_ptr<Motion> harmonic(const CaseReader& in, const Scene&) {
  const double X = in.quantity("cavity.motion.amplitude", dim::length);
  const double f = in.quantity("cavity.motion.frequency", dim::frequency);
  const Vec3 dir = in.vector("cavity.motion.direction", dim::none, Vec3::UnitX());
  const double phase = in.quantity("cavity.motion.phase", dim::angle, 0.0);
  if (!(X >= 0)) in.fail("cavity.motion.amplitude", "must be >= 0");
  if (!(f > 0)) in.fail("cavity.motion.frequency", "must be > 0");
  if (dir.norm() == 0) in.fail("cavity.motion.direction", "must not be the zero vector");
  return make_harmonic_motion(X, f, dir, phase);
}

std::unique_ptr<Motion> table(const CaseReader& in, const Scene& s) {
  const std::string key = "cavity.motion.file";
  const std::string path = in.file_path(key, s.case_dir);
  std::ifstream file(path);
  if (!file) in.fail(key, "cannot open the file " + path);
  std::vector<double> t;
  std::vector<Vec3> x;
  std::string line;
  std::getline(file, line);  // header
  for (int row = 2; std::getline(file, line); ++row) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    for (char& c : line)
      if (c == ',') c = ' ';
    std::istringstream r(line);
    double tt;
    Vec3 p;
    if (!(r >> tt >> p.x() >> p.y() >> p.z()))
      in.fail(key, path + " row " + std::to_string(row) + ": expected 4 numbers t, x, y, z (SI)");
    if (!t.empty() && !(tt > t.back()))
      in.fail(key, path + " row " + std::to_string(row) + ": times must increase strictly");
    t.push_back(tt);
    x.push_back(p);
  }
  if (t.size() < 2) in.fail(key, path + " needs at least two rows");
  return make_table_motion(std::move(t), std::move(x), path);
}

struct MotionKind {
  const char* name;
  std::unique_ptr<Motion> (*parse)(const CaseReader&, const Scene&);
};
const MotionKind kMotionKinds[] = {{"fixed", fixed}, {"harmonic", harmonic}, {"table", table}};

}  // namespace

void resolve_motion(const CaseReader& in, Scene& s) {
  std::vector<std::string> names;
  for (const auto& k : kMotionKinds) names.emplace_back(k.name);
  const std::string kind = in.choice("cavity.motion.kind", names, "fixed");
  std::unique_ptr<Motion> m;
  for (const auto& k : kMotionKinds)
    if (kind == k.name) m = k.parse(in, s);
  if (kind != "fixed") {  // nothing to ramp at rest; a ramp key under "fixed" is an unknown key
    const std::string key = "cavity.motion.ramp";
    const double ramp = in.quantity(key, dim::time, 0.0);
    if (!(ramp >= 0)) in.fail(key, "must be >= 0");
    if (!std::isfinite(ramp)) in.fail(key, "must be finite (s)");
    if (ramp > 0) m = make_ramped_motion(std::move(m), ramp);
  }
  s.motion = std::move(m);
}

}  // namespace bagdem
