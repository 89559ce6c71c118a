// [[dampers]]: several dampers on one structure. The case's own damper is the case as written; each
// entry of [[dampers]] is another, written as the keys it changes:
//
//   [damper]                        # the case's own damper (optional)
//   name = "tip"
//   [[dampers]]
//   name = "mid"                    # default: its place, "2", "3", ...
//   set = ['primary.attach = "0.335 m"', 'bag.balls.mass_ratio = 0.03']
//
// A damper may change its cavity, its contents and materials, where and how it is attached
// (kDamperKeys); the structure, its excitation, the run and its output are the case's. Each damper
// is the whole case resolved again with its keys (load_case), so every key means there what it
// means in a case. The resolved dampers then share one structure: each one's Primary carries the
// mass of every cavity (primary.cavity_mass at each attach point) in its mass matrix, and one step
// (the smallest of theirs; a case that resolves different steps is resolved again at that one).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <set>
#include <sstream>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"

namespace bagdem {
namespace {

// What a damper may change: keys under these (or these keys themselves).
constexpr const char* kDamperKeys[] = {"cavity",         "bag",           "particles",       "materials",
                                       "interactions",   "primary.attach", "primary.cavity_mass",
                                       "primary.direction", "primary.axis", "primary.follow_slope", "simulation.gravity"};

// A damper's name names its directory (OUT/dampers/NAME): letters, digits, '_', '-' and '.', at
// most 64, not "." or "..".
constexpr std::size_t kMaxNameLength = 64;
bool name_ok(const std::string& n) {
  if (n.empty() || n.size() > kMaxNameLength || n == "." || n == "..") return false;
  return std::all_of(n.begin(), n.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'; });
}
const char* kNameRule = "must be a name of 1 to 64 letters, digits, '_', '-' or '.' (not \".\" or \"..\"): it names the damper's outputs, "
                        "OUT/dampers/NAME";

std::string trimmed(const std::string& s) {
  const auto a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// A damper's orientation is its cavity's frame turned: the structure's direction and axis and
// gravity, written in it, must relate to one another as the case's do (gravity's components along
// the direction, the axis and their normal the same).
void require_a_rotation(const Scene& s, const Scene& d, const std::string& name) {
  auto components = [](const Scene& x) {
    const Vec3 e = x.primary->direction.normalized(), a = x.primary->axis.normalized();
    return Vec3(x.gravity.dot(e), x.gravity.dot(a), x.gravity.dot(e.cross(a)));
  };
  const Vec3 c0 = components(s), c = components(d);
  if ((c - c0).norm() <= 1e-9 * std::max(1.0, s.gravity.norm())) return;
  std::ostringstream m;
  m << "damper '" << name << "': its primary.direction, primary.axis and simulation.gravity are not the case's turned (gravity along "
    << "the direction, the axis and their normal: [" << c.transpose() << "] m/s^2 against the case's [" << c0.transpose()
    << "]): a damper's orientation turns all three together; give them so, or leave them the case's";
  throw InputError(s.case_file, "dampers", "", m.str());
}

}  // namespace

bool damper_may_change(const std::string& key) {
  return std::any_of(std::begin(kDamperKeys), std::end(kDamperKeys), [&](const char* k) {
    const std::string p = k;
    return key == p || key.rfind(p + ".", 0) == 0;
  });
}

std::string damper_keys_text() {
  std::string t;
  for (const char* k : kDamperKeys) t += (t.empty() ? "" : ", ") + std::string(k);
  return t;
}


std::vector<DamperKeys> read_dampers(const CaseReader& in) {
  std::vector<DamperKeys> out;
  const std::string own = in.string("damper.name", "1");
  if (!name_ok(own)) in.fail("damper.name", kNameRule);
  std::set<std::string> names{own};
  const std::size_t n = in.array_size("dampers");
  for (std::size_t k = 0; k < n; ++k) {
    const std::string at = "dampers." + std::to_string(k);
    DamperKeys d;
    const bool named = in.has(at + ".name");
    d.name = in.string(at + ".name", std::to_string(k + 2));
    if (!name_ok(d.name)) in.fail(at + ".name", kNameRule);
    if (!names.insert(d.name).second)
      in.fail(at + ".name", named ? "is the name of another damper: each damper's name must be its own"
                                  : "is not given, and its default, \"" + d.name + "\" (its place), is another damper's name: give it one");
    const std::size_t sets = in.array_size(at + ".set");
    if (sets == 0) in.fail(at + ".set", "must list the keys this damper changes, e.g. ['primary.attach = \"0.3 m\"'] (a damper like the case's own would sit on it)");
    for (std::size_t j = 0; j < sets; ++j) {
      const std::string key = at + ".set." + std::to_string(j);
      const std::string text = in.string(key);
      const auto eq = text.find('=');
      const std::string changed = eq == std::string::npos ? "" : trimmed(text.substr(0, eq));
      if (changed.empty()) in.fail(key, "must be KEY = VALUE (TOML), e.g. 'primary.attach = \"0.3 m\"'");
      if (!damper_may_change(changed))
        in.fail(key, "changes " + changed + ": a damper may change only the keys under " + damper_keys_text() +
                         " (written as dotted keys, unquoted); the structure, its excitation, the run and its output are the case's, shared");
      d.set.push_back(changed + "=" + trimmed(text.substr(eq + 1)));
    }
    out.push_back(std::move(d));
  }
  return out;
}


void join_dampers(Scene& s, std::vector<Scene>& others, const std::vector<DamperKeys>& keys) {
  for (std::size_t k = 0; k < others.size(); ++k) {
    require_a_rotation(s, others[k], keys[k].name);
    for (const std::string& w : others[k].warnings) s.warnings.push_back("damper " + keys[k].name + ": " + w);
  }
  // One structure: every cavity's mass in the mass matrix of each.
  Primary all = *s.primary;  // the case's own cavity's mass in it already
  for (const Scene& d : others) all.carry_cavity(d.primary->cavity_mass, d.primary->at_cavity);
  const Eigen::MatrixXd& M = all.mass;
  const Eigen::MatrixXd& M_inverse = all.mass_inverse;
  // A sweep's predicted start (excitation.predict) models one damper's contents: off with several.
  std::shared_ptr<const Primary::SteppedSine> sweep;
  if (s.primary->stepped_sine) {
    auto plan = std::make_shared<Primary::SteppedSine>(*s.primary->stepped_sine);
    plan->predict = false;
    sweep = plan;
  }
  auto shared = [&](const Scene& d) {
    auto P = std::make_shared<Primary>(*d.primary);
    P->mass = M, P->mass_inverse = M_inverse;
    if (sweep) P->stepped_sine = sweep;
    P->start_at = s.primary->at_cavity;  // one steady start for all: the case's own damper's
    return P;
  };
  s.primary = shared(s);
  for (std::size_t k = 0; k < others.size(); ++k) {
    others[k].primary = shared(others[k]);
    others[k].output = s.output;  // the case's: one set of samples for the structure and every damper
    others[k].damper_name = keys[k].name;
    s.more_dampers.push_back({keys[k].name, std::make_shared<const Scene>(std::move(others[k]))});
  }
}

void refuse_several_dampers(const Scene& s, const std::string& command, const std::string& what) {
  if (s.more_dampers.empty()) return;
  throw InputError(s.case_file, "dampers", "", "the case holds " + std::to_string(1 + s.more_dampers.size()) + " dampers ([[dampers]]); " +
                                                   command + " " + what + ": give it each damper as its own case (`bagdem run` and "
                                                   "`bagdem sweep` run several on the structure)");
}

std::string exact_text(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

}  // namespace bagdem
