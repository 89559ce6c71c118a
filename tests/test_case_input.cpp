// Case input validation through the command line: every bad input gives exit code 2 and a message
// that names the file (the case.toml path), the key, the value and what is allowed; --set overrides;
// `bagdem check` on valid cases reports N, the time step and how it was chosen, and what is modelled.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "support.hpp"

namespace fs = std::filesystem;
using bagdem::testing::TempDir;
using bagdem::testing::CmdResult;
using bagdem::testing::slurp;
using bagdem::testing::run_bagdem;

namespace {

// A small valid case: 5 steel balls of 4 mm in a 20 mm box, no friction, gravity.
const std::string kBase = R"([simulation]
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

[particles.balls]
material = "steel"
diameter = "4 mm"
count = 5
seed = 1
)";

// The same case with explicit particles (positions list) instead of the generated group.
std::string explicit_case(const std::string& positions, const std::string& extra = "") {
  const std::string head = kBase.substr(0, kBase.find("[particles.balls]"));
  return head + "[particles.balls]\nmaterial = \"steel\"\ndiameter = \"4 mm\"\npositions = " + positions +
         "\n" + extra;
}

// `text` with the first occurrence of `from` replaced by `to`; fails the test if `from` is absent.
std::string with(const std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test set-up: '" << from << "' not in the base case";
  if (at == std::string::npos) return text;
  std::string t = text;
  t.replace(at, from.size(), to);
  return t;
}

// A case directory holding `toml` as case.toml.
struct Case {
  TempDir tmp;
  fs::path dir, file;
  explicit Case(const std::string& toml) {
    dir = tmp.path / "case";
    fs::create_directories(dir);
    file = dir / "case.toml";
    std::ofstream(file) << toml;
  }
  CmdResult check(const std::vector<std::string>& sets = {}) const {
    std::vector<std::string> args = {"check", dir.string()};
    for (const auto& s : sets) {
      args.push_back("--set");
      args.push_back(s);
    }
    return run_bagdem(args, tmp.path);
  }
};

// Exit code 2, and stderr names every one of `parts` (file, key, value, what is allowed).
void expect_input_error(const CmdResult& r, const std::vector<std::string>& parts) {
  EXPECT_EQ(r.code, 2) << "stderr: " << r.err << "\nstdout: " << r.out;
  for (const auto& p : parts)
    EXPECT_NE(r.err.find(p), std::string::npos) << "the message lacks '" << p << "':\n" << r.err;
}

// Expects the bad case `toml` to be refused by `check` naming its file and every one of `parts`.
void expect_refused(const std::string& toml, const std::vector<std::string>& parts) {
  Case c(toml);
  std::vector<std::string> all = {c.file.string()};
  all.insert(all.end(), parts.begin(), parts.end());
  expect_input_error(c.check(), all);
}

TEST(CaseInput, BaseCaseIsValid) {
  // Every refusal below is a one-line change of this case, so it must itself pass.
  Case c(kBase);
  const CmdResult r = c.check();
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("N = 5,"), std::string::npos) << r.out;
}

TEST(CaseInput, UnknownTopLevelKey) {
  expect_refused("colour = \"red\"\n" + kBase, {"'colour'", "\"red\"", "unknown key"});
  // A misspelt table is unknown too.
  expect_refused(kBase + "\n[outptu]\nframe_interval = \"1 ms\"\n", {"'outptu'", "unknown key"});
}

TEST(CaseInput, UnknownNestedKey) {
  expect_refused(with(kBase, "poisson_ratio = 0.3\n", "poisson_ratio = 0.3\ndensty = 7777\n"),
                 {"'materials.steel.densty'", "7777", "unknown key in [materials.steel]"});
  expect_refused(with(kBase, "seed = 1\n", "seed = 1\ncuont = 12\n"),
                 {"'particles.balls.cuont'", "12", "unknown key in [particles.balls]"});
}

TEST(CaseInput, StringWhereNumberExpected) {
  expect_refused(with(kBase, "density = \"7800 kg/m^3\"", "density = \"abc\""),
                 {"'materials.steel.density'", "\"abc\"", "number", "kg/m^3"});
  // An integer key given a string.
  expect_refused(with(kBase, "count = 5", "count = \"five\""),
                 {"'particles.balls.count'", "\"five\"", "must be an integer"});
}

TEST(CaseInput, WrongUnits) {
  expect_refused(with(kBase, "diameter = \"4 mm\"", "diameter = \"4 Hz\""),
                 {"'particles.balls.diameter'", "\"4 Hz\"", "units of dimension m"});
  expect_refused(with(kBase, "duration = \"0.01 s\"", "duration = \"10 mm\""),
                 {"'simulation.duration'", "\"10 mm\"", "units of dimension s"});
}

TEST(CaseInput, MissingRequiredKeys) {
  expect_refused(with(kBase, "duration = \"0.01 s\"\n", ""),
                 {"'simulation.duration'", "missing", "is required", "dimension s"});
  expect_refused(with(kBase, "density = \"7800 kg/m^3\"\n", ""),
                 {"'materials.steel.density'", "missing", "is required", "kg/m^3"});
}

TEST(CaseInput, NegativeDensity) {
  expect_refused(with(kBase, "density = \"7800 kg/m^3\"", "density = -7800"),
                 {"'materials.steel.density'", "-7800", "must be > 0"});
}

TEST(CaseInput, RestitutionOutOfRange) {
  expect_refused(with(kBase, "restitution = 0.5", "restitution = 0"),
                 {"'interactions.default.restitution'", "= 0:", "must be in (0, 1]"});
  expect_refused(with(kBase, "restitution = 0.5", "restitution = 1.5"),
                 {"'interactions.default.restitution'", "1.5", "must be in (0, 1]"});
}

TEST(CaseInput, PoissonRatioOutOfRange) {
  expect_refused(with(kBase, "poisson_ratio = 0.3", "poisson_ratio = 0.5"),
                 {"'materials.steel.poisson_ratio'", "0.5", "must be in (-1, 0.5)"});
  expect_refused(with(kBase, "poisson_ratio = 0.3", "poisson_ratio = -1"),
                 {"'materials.steel.poisson_ratio'", "-1", "must be in (-1, 0.5)"});
}

TEST(CaseInput, ParticlesLargerThanCavity) {
  expect_refused(with(kBase, "diameter = \"4 mm\"", "diameter = \"25 mm\""),
                 {"'particles.balls.diameter'", "\"25 mm\"", "larger than the cavity"});
  // The same for an explicit particle.
  expect_refused(with(explicit_case("[[\"10 mm\", \"10 mm\", \"10 mm\"]]"), "diameter = \"4 mm\"",
                      "diameter = \"30 mm\""),
                 {"'particles.balls.positions'", "10 mm", "larger than the cavity"});
}

TEST(CaseInput, OverlappingExplicitParticles) {
  // Centres 3 mm apart, diameter 4 mm.
  expect_refused(explicit_case("[[\"10 mm\", \"10 mm\", \"10 mm\"], [\"13 mm\", \"10 mm\", \"10 mm\"]]"),
                 {"'particles.balls.positions'", "13 mm", "overlap", "must not overlap"});
  // Centres 4.1 mm apart do not overlap: accepted.
  Case ok(explicit_case("[[\"10 mm\", \"10 mm\", \"10 mm\"], [\"14.1 mm\", \"10 mm\", \"10 mm\"]]"));
  const CmdResult r = ok.check();
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("N = 2,"), std::string::npos) << r.out;
}

TEST(CaseInput, ExplicitParticleOutsideCavity) {
  expect_refused(explicit_case("[[\"10 mm\", \"10 mm\", \"10 mm\"], [\"30 mm\", \"10 mm\", \"10 mm\"]]"),
                 {"'particles.balls.positions'", "30 mm", "not inside the cavity"});
  // Crossing a wall (centre inside, 1 mm from the +x wall) is outside too.
  expect_refused(explicit_case("[[\"19 mm\", \"10 mm\", \"10 mm\"]]"),
                 {"'particles.balls.positions'", "19 mm", "not inside the cavity"});
}

TEST(CaseInput, ExplicitTimestepAboveCritical) {
  // The critical step of this case is about 5.3e-6 s.
  const std::string toml = with(kBase, "duration = \"0.01 s\"\n", "duration = \"0.01 s\"\ntimestep = \"1e-5 s\"\n");
  expect_refused(toml, {"'simulation.timestep'", "\"1e-5 s\"", "above the critical step", "force_timestep"});
  // force_timestep = true accepts it, and check says it is explicit.
  Case forced(with(toml, "timestep = \"1e-5 s\"\n", "timestep = \"1e-5 s\"\nforce_timestep = true\n"));
  const CmdResult r = forced.check();
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("time step   1e-05 s (explicit"), std::string::npos) << r.out;
  // A step below the critical one is accepted without force.
  Case below(with(kBase, "duration = \"0.01 s\"\n", "duration = \"0.01 s\"\ntimestep = \"1e-6 s\"\n"));
  EXPECT_EQ(below.check().code, 0);
}

TEST(CaseInput, UnknownCavityKind) {
  expect_refused(with(kBase, "kind = \"box\"", "kind = \"sphere\""),
                 {"'cavity.kind'", "\"sphere\"", "must be one of", "\"box\"", "\"cylinder\"", "\"planes\""});
}

TEST(CaseInput, MissingCaseDirectory) {
  TempDir tmp;
  const fs::path missing = tmp.path / "no_such_case";
  const CmdResult r = run_bagdem({"check", missing.string()}, tmp.path);
  expect_input_error(r, {(missing / "case.toml").string(), "no case.toml"});
  // `run` refuses it the same way and writes nothing.
  const CmdResult r2 = run_bagdem({"run", missing.string(), "--out", (tmp.path / "out").string(), "--quiet"}, tmp.path);
  expect_input_error(r2, {(missing / "case.toml").string(), "no case.toml"});
  EXPECT_FALSE(fs::exists(tmp.path / "out" / "results.h5"));
}

TEST(CaseInput, InvalidTomlSyntax) {
  const std::string toml = with(kBase, "count = 5", "count = = 5");
  // Line of the bad entry, 1-based.
  const auto at = toml.find("count = = 5");
  const long line = 1 + std::count(toml.begin(), toml.begin() + static_cast<long>(at), '\n');
  Case c(toml);
  expect_input_error(c.check(), {c.file.string() + ":" + std::to_string(line) + ":", "not valid TOML"});
  // An unterminated string.
  Case c2(with(kBase, "kind = \"box\"", "kind = \"box"));
  expect_input_error(c2.check(), {c2.file.string() + ":", "not valid TOML"});
}

TEST(CaseInput, SetOverridesApply) {
  Case c(kBase);
  CmdResult r = c.check({"particles.balls.count=7"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("N = 7,"), std::string::npos) << r.out;
  // A quantity with units (TOML string) and a key the file does not have.
  r = c.check({"simulation.duration=\"0.02 s\"", "simulation.settle=\"5 ms\""});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("settle 0.005 s + measured 0.02 s"), std::string::npos) << r.out;
  // Friction switched on from the command line turns the tangential model on.
  r = c.check({"interactions.default.friction=0.3"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Coulomb cap:               on"), std::string::npos) << r.out;
}

TEST(CaseInput, BadSetValues) {
  Case c(kBase);
  expect_input_error(c.check({"particles.balls.count=abc"}),
                     {c.file.string(), "'particles.balls.count'", "\"abc\"", "must be an integer"});
  expect_input_error(c.check({"particles.balls.count=-3"}),
                     {c.file.string(), "'particles.balls.count'", "-3", "between 1 and 5e7"});
  expect_input_error(c.check({"materials.steel.densty=3"}),
                     {c.file.string(), "'materials.steel.densty'", "unknown key"});
  expect_input_error(c.check({"particles.balls.diameter=\"4 Hz\""}),
                     {c.file.string(), "'particles.balls.diameter'", "\"4 Hz\"", "units of dimension m"});
  expect_input_error(c.check({"noequals"}), {"--set noequals", "key=value"});
}

TEST(CaseInput, ExampleCasePassesCheck) {
  TempDir tmp;
  const fs::path pdbox = fs::path(BAGDEM_CASES_DIR) / "pdbox";
  const CmdResult r = run_bagdem({"check", pdbox.string()}, tmp.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("N = 100,"), std::string::npos) << r.out;
  // Its step is explicit (2e-7 s, as the peers) and its friction 0.3 turns the tangential model on.
  EXPECT_NE(r.out.find("time step   2e-07 s (explicit"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Coulomb cap:               on"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rolling resistance (EPSD2):                             off"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("harmonic"), std::string::npos) << r.out;
}

TEST(CaseInput, CheckReportsTimestepAndModels) {
  Case c(kBase);
  CmdResult r = c.check();
  ASSERT_EQ(r.code, 0) << r.err;
  // The step, how it was chosen, and which limit won.
  EXPECT_NE(r.out.find("time step   "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(auto: min of 0.2 x Rayleigh"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("contact time (or damping time when e is low) / 40"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("half the critical step"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("limits; expected impact speed"), std::string::npos) << r.out;
  // Friction 0: tangential off, and so rotation; gravity on.
  EXPECT_NE(r.out.find("Coulomb cap:               off (no pair has friction)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rotation integration:                                   off"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("gravity:                                                on"), std::string::npos) << r.out;

  // Rolling friction on, gravity off.
  r = c.check({"interactions.default.rolling_friction=0.05", "simulation.gravity=[0, 0, 0]"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("rolling resistance (EPSD2):                             on"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rotation integration:                                   on"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("gravity:                                                off"), std::string::npos) << r.out;
}

}  // namespace
