// The damper a map characterises, recorded beside it (OUT/damper.toml) so that a map is never
// applied to another damper: `bagdem predict` and `bagdem design` compare the record with the
// case's and refuse a case whose damper differs, naming the keys.
//
// The record is the case's keys that make the damper, each value in SI as text ("4 mm" and 0.004
// are the same; a plain number is SI): every key of [bag], [particles] and [cavity] but its motion,
// the [materials] they name, [interactions], simulation.gravity, and the direction the contents are
// shaken in (primary.direction, or the cavity's harmonic motion), and a time step the case fixes
// (simulation.timestep other than "auto", force_timestep when true; at the automatic step its factors,
// timestep_safety, steps_per_contact and expected_speed, compared only where the map's record holds
// them). A key of those tables the case leaves out, or gives at its default value, is recorded as
// "(default) VALUE" (CaseReader::defaults): the same damper as the key given at that value, or not
// recorded at all (a map made before). A bag filled to a mass ratio of a
// structure's mass records that mass as bag.balls.primary_mass, as the map's runs pin it. Where the
// bag sits on the structure (primary.attach), the structure itself and the drive are not the
// damper's: a map serves them all.
#pragma once
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bagdem/reduce/predict.hpp"
#include "bagdem/scene.hpp"

namespace bagdem::study {

using DamperRecord = std::map<std::string, std::string>;  // dotted key -> its value in SI, as text

DamperRecord damper_record(const Scene& scene);

// What damper.toml records of the map beside it ([map]): map.csv's fingerprint and the frequency
// bands characterize mapped (nothing is mapped between two).
struct MapRecord {
  std::string csv;                                // "fnv1a64 HEX, N bytes"
  std::vector<std::pair<double, double>> bands;   // (unit: Hz)
};
// damper.toml: the record as a [damper] table, and (when given) the map's as [map], written
// atomically.
void write_damper_record(const std::filesystem::path& path, const DamperRecord& record, const std::optional<MapRecord>& map = std::nullopt);
// The fingerprint of a file's bytes as damper.toml records map.csv's ("fnv1a64 HEX, N bytes").
std::string file_print(const std::filesystem::path& path);
// map.csv read (reduce/predict.hpp, read_effective_map) once it is the file characterize wrote: its
// fingerprint the one damper.toml beside it records, with the bands recorded there. InputError
// (exit 2) naming the file when it differs (a map.csv edited or damaged after characterize) or
// [map] is not as written; a map recorded without [map] (an earlier bagdem's) or without
// damper.toml is read as it is, its bands told by the spacing of its lines (EffectiveMap::covers).
EffectiveMap read_recorded_map(const std::filesystem::path& map_csv);
// The record of a damper.toml; std::nullopt when there is no such file; InputError naming the file
// when it is not a record.
std::optional<DamperRecord> read_damper_record(const std::filesystem::path& path);

// Each key whose value differs between a map's record and a case's (or that only one has), as
// "KEY is A in the map, B in the case"; empty when the dampers are the same.
std::vector<std::string> damper_differences(const DamperRecord& map, const DamperRecord& case_record);

}  // namespace bagdem::study
