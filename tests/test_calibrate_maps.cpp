// `bagdem calibrate --maps` (study/calibrate_maps.cpp): two keys fitted through the prediction from
// effective-field maps.
// 1. Three configurations (the ball's diameter), each with its own map whose damping rises with the
//    cavity's amplitude, on the SDOF of case_texts.hpp: targets predicted at a known force and
//    damping ratio are fitted back to them (both keys within 1%, every residual below 0.01 dB). On
//    the pipe's beam, each mode's damping ratio (KEY@M) is fitted back likewise, and fitting one
//    mode's keeps the others' (the list is written out to every elastic mode).
// 2. Refused with exit 2 and nothing written: a configuration without its map, a map without
//    damper.toml, a key that changes the damper (found at its bounds, before anything is written),
//    more keys than targets, a mode's element twice or of a mode the structure lacks, a target of a
//    mode the sweep does not evaluate, several keys without maps, an option of the other method
//    (--seeds, --rounds, --jobs with maps; --points without), an OUT that holds the other method's
//    calibration.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bagdem/case/load_case.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/reduce/predict.hpp"
#include "bagdem/study/damper_record.hpp"
#include "case_texts.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using namespace bagdem;

namespace {

const char* kDiameters[] = {"10 mm", "8 mm", "6 mm"};
constexpr double kScale[] = {1.0, 2.0, 4.0};  // each configuration's damping, times C(Gamma)

// C_eff rises with Gamma and saturates: the force matters, not only the damping ratio.
double damping(double scale, double gamma) { return scale * 4 * gamma / (0.3 + gamma); }

// OUT/map-K/map.csv and its damper.toml (the case at diameter K).
// ci: the cells' 95% half-widths ("0", or "nan" for cells of one start).
void write_map(const fs::path& case_dir, const fs::path& dir, int k, const std::string& ci = "0") {
  fs::create_directories(dir);
  std::ofstream m(dir / "map.csv");
  m << "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m],C_eff_ci95 [N s/m]\n";
  for (int i = 0; i <= 30; ++i) {
    const double G = 1e-4 * std::pow(10.0, 6.0 * i / 30);
    for (double f : {15.0, 20.0, 25.0}) m << G << ',' << f << ",0.05," << ci << ',' << damping(kScale[k], G) << ',' << ci << "\n";
  }
  const Scene s = load_case(case_dir.string(), {std::string("particles.ball.diameter=\"") + kDiameters[k] + "\""});
  study::write_damper_record(dir / "damper.toml", study::damper_record(s));
}

// The predicted reduction of mode 1 at diameter K, force F and damping ratio z.
double predicted(const fs::path& case_dir, const fs::path& map_dir, int k, double F, double z) {
  const Scene s = load_case(case_dir.string(), {std::string("particles.ball.diameter=\"") + kDiameters[k] + "\"",
                                                "excitation.amplitude=\"" + std::to_string(F) + " N\"", "primary.damping_ratio=" + std::to_string(z)});
  const EffectiveMap map = read_effective_map(map_dir / "map.csv");
  const auto modes = predict_modes(*s.primary, map, s.primary->amplitude, s.primary->stepped_sine->frequencies, 60, Checks::interval);
  EXPECT_EQ(modes.size(), 1u);
  return modes.at(0).reduction_db;
}

struct MapsSetup {
  bagdem::testing::TempDir t;
  fs::path case_dir, maps, targets;
  MapsSetup() {
    case_dir = t.path / "case", maps = t.path / "maps", targets = t.path / "targets.csv";
    fs::create_directories(case_dir);
    std::ofstream(case_dir / "case.toml") << bagdem::testing::ball_on_sdof_floor();
    std::ofstream csv(targets);
    csv << "mode,reduction_db,particles.ball.diameter\n";
    for (int k = 0; k < 3; ++k) {
      write_map(case_dir, maps / ("map-" + std::to_string(k)), k);
      csv << "1," << predicted(case_dir, maps / ("map-" + std::to_string(k)), k, 0.05, 0.02) << ",\"" << kDiameters[k] << "\"\n";
    }
  }
  std::vector<std::string> command(const std::string& out) const {
    return {"calibrate", case_dir.string(), "--targets", targets.string(), "--points", "60", "--maps", (maps / "map-2").string(), (maps / "map-0").string(),
            (maps / "map-1").string(), "--out", (t.path / out).string()};
  }
};

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(bagdem::testing::slurp(p.string())); }

}  // namespace

TEST(CalibrateMaps, FitsTheForceAndTheDampingRatioThatMadeTheTargets) {
  const MapsSetup s;
  auto r = bagdem::testing::run_bagdem(with(s.command("two"), {"--key", "excitation.amplitude", "--key", "primary.damping_ratio", "--bounds", "\"0.01 N\",\"0.25 N\"",
                                                       "--bounds", "0.005,0.08"}),
                               s.t.path);
  std::printf("%s", r.out.c_str());
  ASSERT_EQ(r.code, 0) << r.err;
  nlohmann::json j = read_json(s.t.path / "two" / "calibration.json");
  ASSERT_EQ(j["keys"].size(), 2u);
  EXPECT_NEAR(j["keys"][0]["value"].get<double>(), 0.05, 0.0005);
  EXPECT_NEAR(j["keys"][1]["value"].get<double>(), 0.02, 0.0002);
  EXPECT_EQ(j["degrees_of_freedom"].get<int>(), 1);
  for (const auto& t : j["targets"]) EXPECT_LT(std::abs(t["residual_dB"].get<double>()), 0.01) << t;
  const TextTable csv = read_text_table(s.t.path / "two" / "calibrate.csv");
  ASSERT_EQ(csv.rows.size(), 3u);
  EXPECT_NE(csv.rows[2][csv.find("map")].find("map-2"), std::string::npos) << "the 6-mm configuration's map";

  // Maps of one start a cell (no intervals: the predictions' ranges are not known) fit alike, each
  // figure weighted by the tolerance (the weight was NaN and every value counted as no fit).
  for (int k = 0; k < 3; ++k) write_map(s.case_dir, s.maps / ("map-" + std::to_string(k)), k, "nan");
  r = bagdem::testing::run_bagdem(with(s.command("one-start"), {"--key", "excitation.amplitude", "--key", "primary.damping_ratio", "--bounds",
                                                               "\"0.01 N\",\"0.25 N\"", "--bounds", "0.005,0.08"}),
                                  s.t.path);
  ASSERT_EQ(r.code, 0) << r.err;
  j = read_json(s.t.path / "one-start" / "calibration.json");
  EXPECT_NEAR(j["keys"][0]["value"].get<double>(), 0.05, 0.0005);
  EXPECT_NEAR(j["keys"][1]["value"].get<double>(), 0.02, 0.0002);
}

// The pipe's beam (cases/pipe-beanbag), swept around modes 1 and 3, with one map and the case's
// damping ratios [0.004, 0.005, 0.008, 0.007] (four elastic modes): mode 1's alone fitted (KEY@1)
// keeps the others, so both targets are met at 0.004; then modes 1 and 3 fitted each on its own.
TEST(CalibrateMaps, FitsADampingRatioPerMode) {
  bagdem::testing::TempDir t;
  const std::string pipe = std::string(BAGDEM_SOURCE_DIR) + "/cases/pipe-beanbag";
  const std::vector<std::string> sets = {"excitation.around_modes=[1, 3]", "primary.damping_ratio=[0.004, 0.005, 0.008, 0.007]"};
  fs::create_directories(t.path / "map");
  {
    std::ofstream m(t.path / "map" / "map.csv");
    m << "gamma [1],frequency [Hz],M_eff [kg],M_eff_ci95 [kg],C_eff [N s/m],C_eff_ci95 [N s/m]\n";
    for (int i = 0; i <= 24; ++i)
      for (double f : {60.0, 120.0, 400.0, 520.0}) m << 1e-4 * std::pow(10.0, 6.0 * i / 24) << ',' << f << ",0.02,0," << 0.5 + 0.2 * i / 24.0 << ",0\n";
    study::write_damper_record(t.path / "map" / "damper.toml", study::damper_record(load_case(pipe, sets)));
  }
  const Scene truth = load_case(pipe, sets);
  const EffectiveMap map = read_effective_map(t.path / "map" / "map.csv");
  std::vector<std::string> targets;
  for (const PredictedMode& m : predict_modes(*truth.primary, map, truth.primary->amplitude, truth.primary->stepped_sine->frequencies, 60, Checks::interval))
    targets.insert(targets.end(), {"--target", "mode=" + std::to_string(m.mode) + ",reduction_db=" + std::to_string(m.reduction_db)});
  ASSERT_EQ(targets.size(), 4u) << "targets of modes 1 and 3";
  auto fit = [&](const std::string& out, const std::vector<std::string>& keys) {
    std::vector<std::string> args = {"calibrate", pipe, "--set", sets[0], "--set", sets[1], "--maps", (t.path / "map").string(), "--scan", "3",
                                     "--points", "60", "--out", (t.path / out).string()};
    args.insert(args.end(), keys.begin(), keys.end());
    args.insert(args.end(), targets.begin(), targets.end());
    const auto r = bagdem::testing::run_bagdem(args, t.path);
    std::printf("%s", r.out.c_str());
    EXPECT_EQ(r.code, 0) << r.err;
    return read_json(t.path / out / "calibration.json");
  };
  nlohmann::json j = fit("one", {"--key", "primary.damping_ratio@1", "--bounds", "0.001,0.03"});
  EXPECT_NEAR(j["keys"][0]["value"].get<double>(), 0.004, 4e-5);
  for (const auto& x : j["targets"]) EXPECT_LT(std::abs(x["residual_dB"].get<double>()), 0.02) << "mode 3 keeps its 0.008: " << x;
  j = fit("two", {"--key", "primary.damping_ratio@1", "--key", "primary.damping_ratio@3", "--bounds", "0.001,0.03", "--bounds", "0.001,0.03"});
  EXPECT_NEAR(j["keys"][0]["value"].get<double>(), 0.004, 4e-5);
  EXPECT_NEAR(j["keys"][1]["value"].get<double>(), 0.008, 8e-5);
  EXPECT_TRUE(j["keys"][0]["ci95_lo"].is_null()) << "two keys, two targets: no degrees of freedom for an interval";
}

TEST(CalibrateMaps, RefusesWhatAMapCannotAnswer) {
  const MapsSetup s;
  // The 6-mm configuration's map missing.
  auto r = bagdem::testing::run_bagdem({"calibrate", s.case_dir.string(), "--targets", s.targets.string(), "--maps", (s.maps / "map-0").string(),
                                (s.maps / "map-1").string(), "--out", (s.t.path / "a").string()},
                               s.t.path);
  std::printf("  missing map: exit %d: %s", r.code, r.err.c_str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no map characterises the damper at particles.ball.diameter = 6 mm"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s.t.path / "a"));
  // A map without damper.toml.
  fs::copy(s.maps / "map-2", s.t.path / "bare");
  fs::remove(s.t.path / "bare" / "damper.toml");
  r = bagdem::testing::run_bagdem({"calibrate", s.case_dir.string(), "--targets", s.targets.string(), "--maps", (s.maps / "map-0").string(),
                           (s.maps / "map-1").string(), (s.t.path / "bare").string(), "--out", (s.t.path / "b").string()},
                          s.t.path);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("records no damper"), std::string::npos) << r.err;
  // A key of the damper.
  r = bagdem::testing::run_bagdem(with(s.command("c"), {"--key", "materials.steel.density", "--bounds", "7000,8000"}), s.t.path);
  std::printf("  key of the damper: exit %d: %s", r.code, r.err.c_str());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("changes the damper"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s.t.path / "c"));
  // Keys that cannot be fitted: more keys than targets, one mode's element twice, a mode the
  // structure lacks, a key the case cannot take as a list (at its bounds): refused, nothing written.
  for (const auto& [keys, why] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"--key", "excitation.amplitude", "--key", "primary.damping_ratio", "--key", "materials.steel.youngs_modulus", "--key",
             "primary.stiffness"},
            "4 keys cannot be fitted to 3 targets"},
           {{"--key", "primary.damping_ratio@01"}, "KEY@M names the element of elastic mode M (1 to 1"},
           {{"--key", "primary.damping_ratio@2"}, "KEY@M names the element of elastic mode M (1 to 1"},
           {{"--key", "primary.damping_ratio@1", "--bounds", "0.005,0.08"}, "key 'primary.damping_ratio@1' = 0.005,0.08: at 0.005"}}) {
    r = bagdem::testing::run_bagdem(with(s.command("e"), keys), s.t.path);
    std::printf("  %s: exit %d: %s", keys[1].c_str(), r.code, r.err.c_str());
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s.t.path / "e"));
  }
  // A target of a mode the case's sweep does not evaluate: refused before the fit.
  std::ofstream(s.t.path / "mode2.csv") << "mode,reduction_db\n2,3.0\n";
  r = bagdem::testing::run_bagdem({"calibrate", s.case_dir.string(), "--targets", (s.t.path / "mode2.csv").string(), "--maps", (s.maps / "map-0").string(),
                                   "--out", (s.t.path / "f").string()},
                                  s.t.path);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("set excitation.around_modes to include mode 2"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s.t.path / "f"));
  // Several bounds without maps (it used to crash), several keys by coupled DEM.
  r = bagdem::testing::run_bagdem({"calibrate", s.case_dir.string(), "--targets", s.targets.string(), "--bounds", "0.01,0.2", "--bounds", "0.01,0.03",
                                   "--out", (s.t.path / "g").string()},
                                  s.t.path);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("coupled DEM calibrates one key"), std::string::npos) << r.err;
  r = bagdem::testing::run_bagdem({"calibrate", s.case_dir.string(), "--targets", s.targets.string(), "--key", "excitation.amplitude", "--key",
                           "primary.damping_ratio", "--out", (s.t.path / "d").string()},
                          s.t.path);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("several keys are fitted on effective-field maps"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s.t.path / "d"));
  // Options of one method given to the other: refused, not ignored.
  for (const auto& [extra, why] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"--seeds", "2"}, "--maps excludes --seeds"}, {{"--rounds", "2"}, "--maps excludes --rounds"}, {{"--jobs", "1"}, "--maps excludes --jobs"}}) {
    r = bagdem::testing::run_bagdem(with(s.command("h"), extra), s.t.path);
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find(why), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(s.t.path / "h"));
  }
  r = bagdem::testing::run_bagdem({"calibrate", s.case_dir.string(), "--targets", s.targets.string(), "--points", "60", "--out", (s.t.path / "i").string()},
                                  s.t.path);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--points requires --maps"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s.t.path / "i"));
  // One OUT holds one method's calibration: rounds of coupled DEM refuse a fit on maps there, and a
  // fit on maps refuses coupled DEM's rounds.
  fs::create_directories(s.t.path / "dem" / "round-00");
  r = bagdem::testing::run_bagdem(with(s.command("dem"), {"--key", "primary.damping_ratio", "--bounds", "0.005,0.08"}), s.t.path);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("holds a calibration by coupled DEM"), std::string::npos) << r.err;
  fs::create_directories(s.t.path / "onmaps");
  std::ofstream(s.t.path / "onmaps" / "calibration.json") << "{\n  \"method\": \"maps\"\n}\n";
  r = bagdem::testing::run_bagdem({"calibrate", s.case_dir.string(), "--targets", s.targets.string(), "--out", (s.t.path / "onmaps").string()}, s.t.path);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("holds a calibration on maps"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s.t.path / "onmaps" / "round-00"));
}
