// Overrides of case keys, built typed (case/overrides.hpp).
#include "bagdem/case/overrides.hpp"

#include <algorithm>
#include <cstdio>

#include "bagdem/case/case_reader.hpp"

namespace bagdem {

std::string short_text(double x) {
  char b[64];
  std::snprintf(b, sizeof b, "%.10g", x);
  return b;
}

std::vector<std::string> keys::all_paths() {
  std::vector<std::string> p;
  for (const QuantityKey* k : {&timestep, &timestep_safety, &steps_per_contact, &duration, &cavity_interval, &skip_cycles,
                               &steady_tolerance, &attach, &motion_amplitude, &motion_frequency, &motion_ramp, &ball_diameter,
                               &mass_ratio, &primary_mass})
    p.push_back(k->path);
  for (const IntegerKey* k : {&seed, &triangles, &bending_interval, &bed_count}) p.push_back(k->path);
  for (const TomlKey* k : {&excitation, &primary, &cavity_motion}) p.push_back(k->path);
  p.push_back(cavity_max.path), p.push_back(bed_file.path);
  for (const QuantityKey& k : {youngs_modulus("NAME"), stiffness("NAME"), friction("NAME"), rolling_friction("NAME")}) p.push_back(k.path);
  return p;
}

bool sets_key(std::string_view set, std::string_view path) {
  set.remove_prefix(std::min(set.size(), set.find_first_not_of(" \t")));  // " key = v" as CaseReader reads it
  if (set.substr(0, path.size()) != path) return false;
  const std::string_view rest = set.substr(path.size());
  const std::size_t at = rest.find_first_not_of(" \t");
  return at != std::string_view::npos && (rest[at] == '=' || rest[at] == '.');
}

Overrides& Overrides::set(const QuantityKey& k, double si) {
  sets_.push_back(k.path + "=" + (k.unit.empty() ? short_text(si) : "\"" + short_text(si) + " " + k.unit + "\""));
  return *this;
}
Overrides& Overrides::set(const IntegerKey& k, long long v) {
  sets_.push_back(k.path + "=" + std::to_string(v));
  return *this;
}
Overrides& Overrides::set(const WordKey& k, std::string_view word) {
  sets_.push_back(k.path + "=" + toml_string(std::string(word)));
  return *this;
}
Overrides& Overrides::set(const VectorKey& k, const Vec3& si) {
  sets_.push_back(k.path + "=[" + short_text(si.x()) + ", " + short_text(si.y()) + ", " + short_text(si.z()) + "]");
  return *this;
}
Overrides& Overrides::set(const TomlKey& k, std::string_view toml) {
  sets_.push_back(k.path + "=" + std::string(toml));
  return *this;
}

}  // namespace bagdem
