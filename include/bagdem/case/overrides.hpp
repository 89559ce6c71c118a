// Overrides of case keys, as the studies build them for the runs they start: the `--set KEY=VALUE`
// texts a run's CaseReader applies, built typed. A key the studies set is named once, below, with
// the kind of its value; a value is written one way per kind: a quantity as its SI value (%.10g;
// with the SI unit where the key has one for readability, e.g. "0.3 m"), an integer in full, a
// word quoted and escaped (toml_string), a vector as an array of SI values, TOML text (an inline
// table, a study's varied value) as given. The keys' meanings: docs/case-schema.md.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "bagdem/vec3.hpp"

namespace bagdem {

// A number as overrides and the study commands' tables write it: 10 significant digits (%.10g;
// "nan", "inf" as printf gives them).
std::string short_text(double x);

struct QuantityKey {
  std::string path;
  std::string unit;  // the SI unit written after the value ("m", "kg"); "" for a bare SI number
};
struct IntegerKey {
  std::string path;
};
struct WordKey {
  std::string path;
};
struct VectorKey {
  std::string path;  // [x, y, z] in SI
};
struct TomlKey {
  std::string path;  // a value written as TOML text, as given: an inline table ({kind = "harmonic"}), a user's value
};

namespace keys {
inline const QuantityKey timestep{"simulation.timestep", ""};
inline const QuantityKey timestep_safety{"simulation.timestep_safety", ""};
inline const QuantityKey steps_per_contact{"simulation.steps_per_contact", ""};
inline const QuantityKey duration{"simulation.duration", "s"};
inline const IntegerKey seed{"simulation.seed"};
inline const QuantityKey cavity_interval{"output.cavity_interval", ""};
inline const QuantityKey skip_cycles{"output.skip_cycles", ""};
inline const QuantityKey steady_tolerance{"excitation.steady_tolerance", ""};
inline const TomlKey excitation{"excitation"};
inline const TomlKey primary{"primary"};
inline const QuantityKey attach{"primary.attach", "m"};
inline const TomlKey cavity_motion{"cavity.motion"};
inline const QuantityKey motion_amplitude{"cavity.motion.amplitude", "m"};
inline const QuantityKey motion_frequency{"cavity.motion.frequency", "Hz"};
inline const QuantityKey motion_ramp{"cavity.motion.ramp", "s"};
inline const VectorKey cavity_max{"cavity.max"};
inline const IntegerKey triangles{"bag.triangles"};
inline const IntegerKey bending_interval{"bag.film.bending_interval"};
inline const QuantityKey ball_diameter{"bag.balls.diameter", "m"};
inline const QuantityKey mass_ratio{"bag.balls.mass_ratio", ""};
inline const QuantityKey primary_mass{"bag.balls.primary_mass", "kg"};
inline const IntegerKey bed_count{"particles.bed.count"};
inline const WordKey bed_file{"particles.bed.file"};
// Keys of a named table: [materials.NAME], [interactions.NAME].
inline QuantityKey youngs_modulus(const std::string& material) { return {"materials." + material + ".youngs_modulus", ""}; }
inline QuantityKey stiffness(const std::string& interaction) { return {"interactions." + interaction + ".stiffness", ""}; }
inline QuantityKey friction(const std::string& interaction) { return {"interactions." + interaction + ".friction", ""}; }
inline QuantityKey rolling_friction(const std::string& interaction) {
  return {"interactions." + interaction + ".rolling_friction", ""};
}
// Every key above (a named table's with NAME), for the test that each is a key of the schema.
std::vector<std::string> all_paths();
}  // namespace keys

// Whether `set` ("KEY=VALUE") sets `path` itself or a key inside it.
bool sets_key(std::string_view set, std::string_view path);

class Overrides {
 public:
  Overrides() = default;
  explicit Overrides(std::vector<std::string> given) : sets_(std::move(given)) {}  // e.g. the user's --set, first
  Overrides& set(const QuantityKey& k, double si);
  Overrides& set(const IntegerKey& k, long long v);
  Overrides& set(const WordKey& k, std::string_view word);
  Overrides& set(const VectorKey& k, const Vec3& si);
  Overrides& set(const TomlKey& k, std::string_view toml);
  const std::vector<std::string>& sets() const& { return sets_; }
  std::vector<std::string> sets() && { return std::move(sets_); }

 private:
  std::vector<std::string> sets_;
};

}  // namespace bagdem
