// Internal to src/study: what `bagdem calibrate` reads (calibrate.cpp with coupled DEM,
// calibrate_maps.cpp with effective-field maps): the measured targets and the configurations they
// were measured at, and a key's values with their unit and bounds.
#pragma once
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "bagdem/scene.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {

struct Target {
  int mode = 0;
  double reduction_db = NAN;
  std::size_t config = 0;  // its configuration: an index into Targets::configs (0 without them)
};

// The targets, and the configurations they were measured at: one case key and its values (none
// when every target is of the case as it is).
struct Targets {
  std::vector<Target> list;
  std::string config_key;
  std::vector<Value> configs;
  std::string where(const Target& t) const { return config_key.empty() ? "" : " at " + config_key + " = " + configs[t.config].given; }
};

// "mode=1,reduction_db=14.9" (--target); InputError naming the option otherwise.
Target parse_target(const std::string& text);

// --targets FILE: a CSV whose header holds mode, reduction_db and at most one more column, a case
// key; its cells are read as --set reads values. Rows with equal cells share a configuration.
Targets read_targets_file(const std::string& path);

// A value of the key in the unit the user wrote it in ("N", "mN"; "" for a plain number), with
// that unit's factor to SI and the SI unit the tables use.
struct Scale {
  std::string unit, si_unit;
  double to_si = 1;
  std::string toml(double v) const { return unit.empty() ? short_text(v) : "\"" + short_text(v) + " " + unit + "\""; }
  std::string given(double v) const { return unit.empty() ? short_text(v) : short_text(v) + " " + unit; }
};

// A number with an optional unit ("0.05 N", "0.02"): the number in its own unit, and the unit into
// `scale`. False when it is not a number with a known unit.
bool read_value(const std::string& given, Scale& scale, double& value);

// The bounds of `key`: `bounds` "lo,hi" read as --set reads values, or (empty) the case's value / 4
// and x 4. InputError naming --bounds otherwise.
std::pair<double, double> read_bounds(const std::string& key, const std::string& bounds, const Scene& s, Scale& scale);

// The elastic mode numbers whose peaks the case's sweep evaluates, over its planned frequencies.
std::vector<int> evaluated_modes(const Primary& P);

// The targets' reductions, each of a mode the case's sweep evaluates (InputError otherwise, naming
// `source`: --target or the targets' file; and when the case has no coupled stepped-sine sweep).
std::vector<double> target_reductions(const Scene& s, const std::vector<Target>& targets, const std::string& source);

// The fit per mode: calibration.json's "mae_dB" list ({mode, figures, mae_dB} per mode, in the
// targets' order of modes), each mode's mean absolute residual over its figures also printed
// (where it has more than one). `residual` per target (dB).
std::string mae_by_mode(const std::vector<Target>& targets, const std::vector<double>& residual);

// Refuses (InputError) an OUT that holds a calibration of the other method: rounds of coupled DEM
// (OUT/round-RR) when `maps`, a calibration on maps (calibration.json's "method": "maps") when not.
// One directory holds one calibration's tables, never the other's under its names.
void require_same_method(const std::string& out, bool maps);

}  // namespace bagdem::study
