// The bad-input catalogue: each entry is a bad case (a one-line change of a valid case, or a --set
// override), a bad study.toml or a bad command line, run through the real `bagdem` binary (`check`
// mostly, which is cheap). Each must exit with code 2 and a message that names the file (where there
// is one), the key, the value and what is allowed. Beside it: the unknown key named with its nearest
// valid key, the warning for a cavity far larger than its contents, and --threads above the cores.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "mesh_support.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::CmdResult;
using bagdem::testing::run_bagdem;
using bagdem::testing::slurp;
using bagdem::testing::TempDir;

namespace {

// Balls in a shaken box: the base of the [simulation], [materials], [interactions], [cavity],
// [cavity.motion], [particles] and [output] entries.
const std::string kShaken = R"([simulation]
duration = "0.01 s"
gravity = [0, 0, "-9.81 m/s^2"]

[materials.steel]
density = "7800 kg/m^3"
youngs_modulus = "200 GPa"
poisson_ratio = 0.3

[interactions.default]
restitution = 0.5
friction = 0.0

[cavity]
kind = "box"
material = "steel"
min = [0, 0, 0]
max = ["20 mm", "20 mm", "20 mm"]

[cavity.motion]
kind = "harmonic"
amplitude = "1 mm"
frequency = "30 Hz"
direction = [1, 0, 0]

[particles.balls]
material = "steel"
diameter = "4 mm"
count = 5
seed = 1

[output]
frame_interval = "1 ms"
)";

// The same balls in a box carried by a mass-spring structure driven by a force: the base of the
// [primary] and [excitation] entries.
std::string sdof_case() {
  std::string t = kShaken;
  const auto a = t.find("[cavity.motion]"), b = t.find("[particles.balls]");
  t.replace(a, b - a, R"([primary]
kind = "sdof"
mass = "2 kg"
stiffness = "50 kN/m"
damping_ratio = 0.01

[excitation]
kind = "harmonic"
amplitude = "5 N"
frequency = "25 Hz"

)");
  return t;
}

enum class Base { shaken, sdof, bag };

// A bad case: `base` with `from` replaced by `to` (when `from` is not empty) and the overrides
// `sets`; `expect` are the key, the value and what is allowed (the file is added).
struct BadCase {
  const char* what;
  Base base;
  std::string from, to;
  std::vector<std::string> sets;
  std::vector<std::string> expect;
};

const std::vector<BadCase>& bad_cases() {
  static const std::vector<BadCase> cases = {
      // [materials]
      {"E = inf", Base::shaken, "youngs_modulus = \"200 GPa\"", "youngs_modulus = inf", {},
       {"'materials.steel.youngs_modulus'", "= inf", "finite", "kg/m/s^2"}},
      {"density nan", Base::shaken, "density = \"7800 kg/m^3\"", "density = nan", {}, {"'materials.steel.density'", "= nan", "finite"}},
      {"E so large the step is 1e-21 s", Base::shaken, "youngs_modulus = \"200 GPa\"", "youngs_modulus = 1e40", {},
       {"'simulation.timestep'", "\"auto\"", "steps", "at most 1e+12 steps", "youngs_modulus"}},
      {"Poisson ratio in metres", Base::shaken, "", "", {"materials.steel.poisson_ratio=\"0.3 m\""},
       {"'materials.steel.poisson_ratio'", "\"0.3 m\"", "has dimension m, expected 1"}},
      {"density typo", Base::shaken, "density = \"7800 kg/m^3\"", "densty = \"7800 kg/m^3\"", {},
       {"'materials.steel.densty'", "unknown key", "did you mean 'materials.steel.density'?"}},
      // [interactions]
      {"friction -inf", Base::shaken, "friction = 0.0", "friction = -inf", {}, {"'interactions.default.friction'", "-inf", "finite"}},
      {"restitution 2", Base::shaken, "restitution = 0.5", "restitution = 2", {}, {"'interactions.default.restitution'", "= 2", "(0, 1]"}},
      {"pair of unknown material", Base::shaken, "", "", {"interactions.steel-brass.restitution=0.5"},
       {"'interactions.steel-brass'", "must be named \"<material>-<material>\""}},
      {"rolling friction typo", Base::shaken, "", "", {"interactions.default.rolling_frction=0.1"},
       {"'interactions.default.rolling_frction'", "= 0.1:", "did you mean 'interactions.default.rolling_friction'?"}},
      {"law unknown", Base::shaken, "", "", {"interactions.default.law=\"walton\""},
       {"'interactions.default.law'", "\"walton\"", "must be one of \"hertz-mindlin\", \"hooke\""}},
      {"hooke without stiffness", Base::shaken, "", "", {"interactions.default.law=\"hooke\""},
       {"'interactions.default.stiffness'", "(missing)", "is required with law = \"hooke\"", "> 0"}},
      {"hooke stiffness negative", Base::shaken, "", "", {"interactions.default.law=\"hooke\"", "interactions.default.stiffness=-5"},
       {"'interactions.default.stiffness'", "-5", "must be > 0 (N/m)"}},
      {"hooke stiffness ratio above 1", Base::shaken, "", "", {"interactions.default.law=\"hooke\"", "interactions.default.stiffness=\"1e5 N/m\"", "interactions.default.stiffness_ratio=3"},
       {"'interactions.default.stiffness_ratio'", "3", "must be in (0, 1]"}},
      {"stiffness with hertz-mindlin", Base::shaken, "", "", {"interactions.default.stiffness=\"1e5 N/m\""},
       {"'interactions.default.stiffness'", "\"1e5 N/m\"", "law = \"hooke\" only", "\"hertz-mindlin\""}},
      // [particles]
      {"count not whole", Base::shaken, "count = 5", "count = 5.5", {}, {"'particles.balls.count'", "5.5", "must be an integer"}},
      {"count 1e8", Base::shaken, "count = 5", "count = 100000000", {}, {"'particles.balls.count'", "100000000", "between 1 and 5e7"}},
      {"diameter inf mm", Base::shaken, "diameter = \"4 mm\"", "diameter = \"inf mm\"", {},
       {"'particles.balls.diameter'", "\"inf mm\"", "not a finite number"}},
      {"velocity nan", Base::shaken, "", "", {"particles.balls.velocity=[nan, 0, 0]"}, {"'particles.balls.velocity'", "[nan, 0, 0]", "finite"}},
      {"velocity 1e200 m/s", Base::shaken, "", "", {"particles.balls.velocity=[1e200, 0, 0]"},
       {"'simulation.timestep'", "resolves to a step of 0 s", "a step > 0", "initial velocities"}},
      {"seed negative", Base::shaken, "seed = 1", "seed = -1", {}, {"'particles.balls.seed'", "-1", "integer from 0 to"}},
      // [cavity]
      {"max inf", Base::shaken, "max = [\"20 mm\", \"20 mm\", \"20 mm\"]", "max = [inf, \"20 mm\", \"20 mm\"]", {},
       {"'cavity.max'", "[inf, \"20 mm\", \"20 mm\"]", "finite", "dimension m"}},
      {"min of two components", Base::shaken, "min = [0, 0, 0]", "min = [0, 0]", {}, {"'cavity.min'", "[0, 0]", "array of 3 components"}},
      {"kind sphere", Base::shaken, "kind = \"box\"", "kind = \"sphere\"", {}, {"'cavity.kind'", "\"sphere\"", "must be one of"}},
      {"material gold", Base::shaken, "material = \"steel\"\nmin", "material = \"gold\"\nmin", {},
       {"'cavity.material'", "\"gold\"", "must name a material"}},
      {"cylinder radius nan", Base::shaken, "", "", {"cavity.kind=\"cylinder\"", "cavity.radius=nan", "cavity.length=\"20 mm\""},
       {"'cavity.radius'", "nan", "finite"}},
      // [cavity.motion]
      {"amplitude inf", Base::shaken, "amplitude = \"1 mm\"", "amplitude = inf", {}, {"'cavity.motion.amplitude'", "= inf", "finite"}},
      {"amplitude 1e300 m", Base::shaken, "amplitude = \"1 mm\"", "amplitude = \"1e300 m\"", {},
       {"'simulation.timestep'", "step of 0 s", "expected impact speed", "a step > 0", "cavity's motion"}},
      {"frequency in metres", Base::shaken, "frequency = \"30 Hz\"", "frequency = \"30 m\"", {},
       {"'cavity.motion.frequency'", "\"30 m\"", "expected 1/s"}},
      {"direction zero", Base::shaken, "direction = [1, 0, 0]", "direction = [0, 0, 0]", {},
       {"'cavity.motion.direction'", "[0, 0, 0]", "zero vector"}},
      {"motion kind circular", Base::shaken, "kind = \"harmonic\"", "kind = \"circular\"", {},
       {"'cavity.motion.kind'", "\"circular\"", "\"harmonic\""}},
      // [simulation]
      {"duration inf", Base::shaken, "duration = \"0.01 s\"", "duration = inf", {}, {"'simulation.duration'", "inf", "finite"}},
      {"duration typo", Base::shaken, "duration = \"0.01 s\"", "duraton = \"0.01 s\"", {},
       {"'simulation.duraton'", "\"0.01 s\"", "did you mean 'simulation.duration'?"}},
      {"step 1e-300 s", Base::shaken, "", "", {"simulation.timestep=\"1e-300 s\""},
       {"'simulation.timestep'", "\"1e-300 s\"", "1e+298 steps", "at most 1e+12 steps"}},
      {"step 0", Base::shaken, "", "", {"simulation.timestep=0"}, {"'simulation.timestep'", "= 0:", "must be > 0"}},
      {"gravity nan", Base::shaken, "gravity = [0, 0, \"-9.81 m/s^2\"]", "gravity = [0, 0, nan]", {},
       {"'simulation.gravity'", "[0, 0, nan]", "finite", "m/s^2"}},
      {"seed negative", Base::shaken, "", "", {"simulation.seed=-1"}, {"'simulation.seed'", "-1", "integer from 0 to"}},
      {"energy limit 1", Base::shaken, "", "", {"simulation.max_energy_error=1"}, {"'simulation.max_energy_error'", "= 1:", "[0, 1)"}},
      {"neighbour octree", Base::shaken, "", "", {"simulation.neighbour=\"octree\""}, {"'simulation.neighbour'", "\"octree\"", "\"hash\""}},
      {"expected speed inf", Base::shaken, "", "", {"simulation.expected_speed=inf"}, {"'simulation.expected_speed'", "inf", "finite"}},
      {"steps per contact 5", Base::shaken, "", "", {"simulation.steps_per_contact=5"}, {"'simulation.steps_per_contact'", "5", ">= 10"}},
      // [output]
      {"frame interval inf", Base::shaken, "frame_interval = \"1 ms\"", "frame_interval = inf", {},
       {"'output.frame_interval'", "inf", "finite"}},
      {"frame interval 0", Base::shaken, "frame_interval = \"1 ms\"", "frame_interval = 0", {}, {"'output.frame_interval'", "= 0:", "> 0"}},
      {"energy yes", Base::shaken, "", "", {"output.energy=\"yes\""}, {"'output.energy'", "\"yes\"", "true or false"}},
      {"frame interval typo", Base::shaken, "frame_interval = \"1 ms\"", "frame_intervl = \"1 ms\"", {},
       {"'output.frame_intervl'", "\"1 ms\"", "did you mean 'output.frame_interval'?"}},
      // [primary]
      {"mass inf", Base::sdof, "mass = \"2 kg\"", "mass = inf", {}, {"'primary.mass'", "inf", "finite", "dimension kg"}},
      {"stiffness in newtons", Base::sdof, "stiffness = \"50 kN/m\"", "stiffness = \"50 kN\"", {},
       {"'primary.stiffness'", "\"50 kN\"", "expected kg/s^2"}},
      {"kind plate", Base::sdof, "kind = \"sdof\"", "kind = \"plate\"", {}, {"'primary.kind'", "\"plate\"", "\"sdof\""}},
      {"damping ratio nan", Base::sdof, "damping_ratio = 0.01", "damping_ratio = nan", {}, {"'primary.damping_ratio'", "nan", "finite"}},
      {"mass typo", Base::sdof, "mass = \"2 kg\"", "mas = \"2 kg\"", {}, {"'primary.mas'", "did you mean 'primary.mass'?"}},
      // [excitation]
      {"force inf", Base::sdof, "amplitude = \"5 N\"", "amplitude = inf", {}, {"'excitation.amplitude'", "inf", "finite"}},
      {"kind chirp", Base::sdof, "kind = \"harmonic\"", "kind = \"chirp\"", {}, {"'excitation.kind'", "\"chirp\"", "\"stepped-sine\""}},
      {"frequency 1e300 Hz", Base::sdof, "frequency = \"25 Hz\"", "frequency = \"1e300 Hz\"", {},
       {"'excitation.frequency'", "\"1e300 Hz\"", "at least 8 steps per cycle"}},
      {"frequency nan", Base::sdof, "frequency = \"25 Hz\"", "frequency = nan", {}, {"'excitation.frequency'", "nan", "finite"}},
      {"a sweep's frequency twice", Base::sdof, "kind = \"harmonic\"\namplitude = \"5 N\"\nfrequency = \"25 Hz\"",
       "kind = \"stepped-sine\"\namplitude = \"5 N\"\nfrequencies = [\"20 Hz\", \"25 Hz\", 25]", {},
       {"'excitation.frequencies'", "gives 25 Hz twice", "each frequency once"}},
      {"a sweep's band of one frequency in 3 points", Base::sdof, "kind = \"harmonic\"\namplitude = \"5 N\"\nfrequency = \"25 Hz\"",
       "kind = \"stepped-sine\"\namplitude = \"5 N\"\nband = [\"25 Hz\", \"25 Hz\"]\npoints = 3", {},
       {"'excitation.band'", "gives 25 Hz twice", "points = 1"}},
      // [bag] (the shipped bean bag)
      {"balls 0", Base::bag, "", "", {"bag.balls.count=0"}, {"'bag.balls.count'", "= 0:", "[1, 1e7]"}},
      {"film thickness inf", Base::bag, "", "", {"bag.film.thickness=inf"}, {"'bag.film.thickness'", "inf", "finite"}},
      {"self radius 0", Base::bag, "", "", {"bag.film.self_contact=true", "bag.film.self_radius=\"0 mm\""}, {"'bag.film.self_radius'", "must be > 0"}},
      {"self radius tiny", Base::bag, "", "", {"bag.film.self_contact=true", "bag.film.self_radius=\"1e-9 mm\""},
       {"'bag.film.self_radius'", "from 0.3 to 0.8 of the film's mean edge", "pass between"}},
      {"self radius huge", Base::bag, "", "", {"bag.film.self_contact=true", "bag.film.self_radius=\"50 mm\""},
       {"'bag.film.self_radius'", "from 0.3 to 0.8 of the film's mean edge", "pressed"}},
      {"triangles 10", Base::bag, "", "", {"bag.triangles=10"}, {"'bag.triangles'", "10", "[20, 2e6]"}},
      {"shape sphere", Base::bag, "", "", {"bag.shape=\"sphere\""}, {"'bag.shape'", "\"sphere\"", "\"capsule\", \"pillow\""}},
      {"string stiffness nan", Base::bag, "", "", {"bag.strings.0.stiffness=nan"}, {"'bag.strings.0.stiffness'", "nan", "finite"}},
      {"fill fraction inf", Base::bag, "", "", {"bag.fill_fraction=inf"}, {"'bag.fill_fraction'", "inf", "finite"}},
      {"mass scaling 0.5", Base::bag, "", "", {"bag.film.mass_scaling=0.5"}, {"'bag.film.mass_scaling'", "0.5", ">= 1"}},
      {"bending interval 0", Base::bag, "", "", {"bag.film.bending_interval=0"}, {"'bag.film.bending_interval'", "0", "from 1 to 64"}},
      {"bending interval 2.5", Base::bag, "", "", {"bag.film.bending_interval=2.5"}, {"'bag.film.bending_interval'", "2.5", "integer"}},
      {"bending interval word", Base::bag, "", "", {"bag.film.bending_interval=\"slow\""},
       {"'bag.film.bending_interval'", "\"slow\"", "\"auto\" or a whole number of steps from 1 to 64"}},
      {"balls seed negative", Base::bag, "", "", {"bag.balls.seed=-3"}, {"'bag.balls.seed'", "-3", "integer from 0 to"}},
      // --set
      {"--set count abc", Base::shaken, "", "", {"particles.balls.count=abc"}, {"'particles.balls.count'", "\"abc\"", "must be an integer"}},
      {"--set duration inf", Base::shaken, "", "", {"simulation.duration=inf"}, {"'simulation.duration'", "inf", "finite"}},
      {"--set unknown table", Base::shaken, "", "", {"simulaton.duration=\"1 s\""}, {"'simulaton'", "did you mean 'simulation'?"}},
  };
  return cases;
}

std::string base_text(Base b) {
  if (b == Base::shaken) return kShaken;
  if (b == Base::sdof) return sdof_case();
  return slurp(fs::path(BAGDEM_CASES_DIR) / "box-beanbag" / "case.toml");
}

// Exit code 2 and every one of `parts` in stderr.
void expect_refused(const CmdResult& r, const std::vector<std::string>& parts) {
  EXPECT_EQ(r.code, 2) << "stderr: " << r.err << "\nstdout: " << r.out;
  for (const auto& p : parts) EXPECT_NE(r.err.find(p), std::string::npos) << "the message lacks '" << p << "':\n" << r.err;
}

TEST(BadInputCatalogue, EveryBaseCaseIsValid) {
  // Each entry is a one-line change of these, so they must pass themselves.
  TempDir tmp;
  for (Base b : {Base::shaken, Base::sdof}) {
    tmp.write("case.toml", base_text(b));
    const CmdResult r = run_bagdem({"check", tmp.str()}, tmp.path);
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out.find("warning"), std::string::npos) << r.out;
  }
  const CmdResult r = run_bagdem({"check", (fs::path(BAGDEM_CASES_DIR) / "box-beanbag").string()}, tmp.path);
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(BadInputCatalogue, CaseKeys) {
  EXPECT_GE(bad_cases().size(), 40u);
  TempDir tmp;
  for (const BadCase& c : bad_cases()) {
    SCOPED_TRACE(c.what);
    fs::path dir = tmp.path / "case", file = dir / "case.toml";
    if (c.base == Base::bag) {
      dir = fs::path(BAGDEM_CASES_DIR) / "box-beanbag";
      file = dir / "case.toml";
    } else {
      std::string text = base_text(c.base);
      if (!c.from.empty()) {
        const auto at = text.find(c.from);
        ASSERT_NE(at, std::string::npos) << "test set-up: '" << c.from << "' not in the base case";
        text.replace(at, c.from.size(), c.to);
      }
      fs::create_directories(dir);
      std::ofstream(file) << text;
    }
    std::vector<std::string> args = {"check", dir.string()};
    for (const auto& s : c.sets) args.insert(args.end(), {"--set", s});
    std::vector<std::string> parts = {file.string() + ": key "};
    parts.insert(parts.end(), c.expect.begin(), c.expect.end());
    expect_refused(run_bagdem(args, tmp.path), parts);
  }
}

TEST(BadInputCatalogue, StudyFiles) {
  // study.toml beside a valid case; `bagdem sweep --check` plans the study and loads every point.
  struct Entry {
    const char* what;
    std::string toml;
    std::vector<std::string> expect;
  };
  const std::vector<Entry> entries = {
      {"seeds 0", "case = \"case\"\nseeds = 0\n", {"'seeds'", "= 0:", "integer from 1 to 100000"}},
      {"jobs not whole", "case = \"case\"\njobs = 1.5\n", {"'jobs'", "1.5", "integer from 1"}},
      {"vary typo", "case = \"case\"\nvarry = { \"particles.balls.count\" = [3, 4] }\n", {"'varry'", "did you mean 'vary'?"}},
      {"combine mix", "case = \"case\"\ncombine = \"mix\"\n", {"'combine'", "\"mix\"", "\"grid\" or \"zip\""}},
      {"fidelity best", "case = \"case\"\nfidelity = \"best\"\n", {"'fidelity'", "\"best\"", "\"fast\""}},
      {"a varied value inf", "case = \"case\"\n[vary]\n\"simulation.duration\" = [0.01, inf]\n",
       {"does not load", "'simulation.duration'", "inf", "finite"}},
  };
  TempDir tmp;
  fs::create_directories(tmp.path / "study" / "case");
  std::ofstream(tmp.path / "study" / "case" / "case.toml") << kShaken;
  const std::string file = (tmp.path / "study" / "study.toml").string();
  for (const Entry& e : entries) {
    SCOPED_TRACE(e.what);
    std::ofstream(file) << e.toml;
    std::vector<std::string> parts = e.expect;
    parts.push_back(e.what == std::string("a varied value inf") ? "case.toml" : file);
    expect_refused(run_bagdem({"sweep", (tmp.path / "study").string(), "--check"}, tmp.path), parts);
  }
}

TEST(BadInputCatalogue, CommandLines) {
  // CLI11's message, and exit code 2 like every other bad input (not CLI11's own codes 105-109).
  TempDir tmp;
  const fs::path dir = tmp.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << kShaken;
  const std::string c = dir.string();
  const std::string afile = (tmp.path / "afile").string();  // an --out that is a file: exit 2, not a library error (exit 1)
  std::ofstream(afile) << "mine\n";
  struct Entry {
    std::vector<std::string> args;
    std::vector<std::string> expect;
  };
  const std::vector<Entry> entries = {
      {{"drop", c, "--out", afile}, {"--out", "is a file, not a directory"}},
      {{"run", c, "--out", afile}, {"--out", "is a file, not a directory"}},
      {{"run"}, {"case_dir is required"}},
      {{"run", c, "--threads", "0"}, {"--threads", "0", "not in range 1 to 1024"}},
      {{"check", c, "--bogus"}, {"--bogus", "not expected"}},
      {{"check", c, "--fidelity", "best"}, {"--fidelity", "best", "fast"}},
      {{"reduce"}, {"case_dir is required"}},
      {{"compare", c, "--form", "x"}, {"--form", "x", "consistent"}},
      {{"drop", c, "--speed", "abc"}, {"--speed", "'abc'", "not a launch speed", "> 0"}},
      {{"drop", c, "--speed", "-1"}, {"--speed", "'-1'", "not a launch speed", "> 0"}},  // used to run at the default
      {{"drop", c, "--speed", "0"}, {"--speed", "'0'", "not a launch speed", "> 0"}},
      {{"drop", c, "--speed", "1e300"}, {"--speed", "'1e300'", "give at most 20 m/s"}},  // ran, then stopped as diverged (exit 3)
      {{"drop", c, "--speed", "1e-300"}, {"--speed", "1e-300", "is too slow", "give at least"}},  // ran for ever, its vectors growing
      {{"export", c, "--formats", "xml"}, {"--formats", "xml", "csv"}},
      {{"bench", "--sizes", "x"}, {"--sizes", "x", "Could not convert"}},
      {{"sweep", c, "--jobs", "0"}, {"--jobs", "0", "not in range 1 to 4096"}},
      {{"trade", c, "--threads", "-1"}, {"--threads", "-1", "not in range 1 to 4096"}},
      {{"design", c, "--budget", "nan"}, {"--budget", "nan", "not in range"}},  // was blamed on bag.balls.mass_ratio
      {{"characterize", c, "--window-time", "nan"}, {"--window-time", "nan", "not in range"}},  // ran with 0
      {{"design", c, "--skip-time", "1x"}, {"--skip-time", "'1x' is not a number"}},
      {{"calibrate", c, "--tolerance", "nan"}, {"--tolerance", "nan", "not in range"}},  // wrote "tolerance_dB": nan into calibration.json
      {{"bench", "--steps", "nan"}, {"--steps", "nan", "not in range"}},
      {{"characterize", c, "--gamma", "0.1,inf", "--band", "10,20", "--check"}, {"--gamma", "both finite"}},  // was a point's 'amplitude -nan m'
      {{}, {"A subcommand is required"}},
      {{"simulate", c}, {"unknown subcommand 'simulate'", "the subcommands are check, run", "design"}},  // was "A subcommand is required"
  };
  for (const Entry& e : entries) {
    std::string line = "bagdem";
    for (const auto& a : e.args) line += " " + a;
    SCOPED_TRACE(line);
    expect_refused(run_bagdem(e.args, tmp.path), e.expect);
  }
  // Help still succeeds.
  EXPECT_EQ(run_bagdem({"run", "--help"}, tmp.path).code, 0);
}

TEST(BadInput, UnknownKeyNamesTheNearestKey) {
  TempDir tmp;
  // A typo of a required key names the typo, not only the missing key.
  std::string text = kShaken;
  text.replace(text.find("duration ="), 10, "duraton =");
  tmp.write("case.toml", text);
  CmdResult r = run_bagdem({"check", tmp.str()}, tmp.path);
  expect_refused(r, {(tmp.path / "case.toml").string() + ": key 'simulation.duraton' = \"0.01 s\": unknown key in [simulation]; "
                                                         "did you mean 'simulation.duration'?"});
  // A key far from every allowed one: the allowed keys of its table are listed.
  tmp.write("case.toml", kShaken);
  r = run_bagdem({"check", tmp.str(), "--set", "cavity.motion.colour=1"}, tmp.path);
  expect_refused(r, {"'cavity.motion.colour'", "unknown key in [cavity.motion]; allowed there:", "amplitude", "frequency"});
  EXPECT_EQ(r.err.find("did you mean"), std::string::npos) << r.err;
}

TEST(BadInput, CavityFarLargerThanItsContentsWarns) {
  TempDir tmp;
  tmp.write("box.stl", bagdem::testing::ascii_stl(bagdem::testing::box_soup(bagdem::Vec3(0, 0, 0), bagdem::Vec3(40, 40, 40), 1)));
  // A 40 mm box as an STL file in millimetres, with 10 balls of 4 mm (mesh_support.hpp, stl_case).
  // Without scale the file's 40 is 40 m: a cavity 1000 times the size of 10 balls of 4 mm.
  tmp.write("case.toml", bagdem::testing::stl_case("box.stl", ""));
  CmdResult r = run_bagdem({"check", tmp.str()}, tmp.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("warning: the cavity (40 x 40 x 40 m)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("STL file in millimetres? Set cavity.scale = \"1 mm\""), std::string::npos) << r.out;
  // With the scale, no warning.
  tmp.write("case.toml", bagdem::testing::stl_case("box.stl"));
  r = run_bagdem({"check", tmp.str()}, tmp.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find("warning"), std::string::npos) << r.out;
  // A box given in plain numbers meant as millimetres warns too, naming the cavity's keys.
  tmp.write("case.toml", kShaken);
  r = run_bagdem({"check", tmp.str(), "--set", "cavity.max=[20, 20, 20]"}, tmp.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("warning: the cavity (20 x 20 x 20 m)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cavity.max"), std::string::npos) << r.out;
}

TEST(BadInput, ThreadsAboveTheCoresWarnAndRun) {
  TempDir tmp;
  tmp.write("case.toml", kShaken);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::vector<std::string> args = {"run", tmp.str(), "--out", (tmp.path / "out").string(), "--quiet",
                                         "--set", "simulation.duration=\"0.2 ms\"", "--threads"};
  std::vector<std::string> over = args, one = args;
  over.push_back(std::to_string(cores + 1));
  one.push_back("1");
  CmdResult r = run_bagdem(over, tmp.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: --threads " + std::to_string(cores + 1) + " is more than the"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(tmp.path / "out" / "summary.json"));
  r = run_bagdem(one, tmp.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

}  // namespace
