// The case features a user composes scenes from: cavity kinds, motion kinds, particle sources.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <tuple>
#include <numbers>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/step/simulation.hpp"
#include "bagdem/study/damper_record.hpp"
#include "case_texts.hpp"
#include "support.hpp"

using namespace bagdem;
using bagdem::testing::TempDir;
using namespace bagdem::testing;

namespace {
// A temporary case directory holding `toml` as case.toml.
struct CaseDir : TempDir {
  explicit CaseDir(const std::string& toml) { write("case.toml", toml); }
};
}  // namespace

namespace {

// 1 ms of steel balls in a 21 x 21 x 48 mm steel box under gravity (the particles are the test's).
CaseText in_box() { return steel_scene("1 ms").box("steel", "[0, 0, 0]", vec("21 mm", "21 mm", "48 mm")); }

double min_gap(const Scene& s) {  // smallest surface gap between two particles (brute force)
  double g = 1e300;
  for (std::size_t a = 0; a < s.particles.size(); ++a)
    for (std::size_t b = a + 1; b < s.particles.size(); ++b)
      g = std::min(g, (s.particles[a].x - s.particles[b].x).norm() - s.particles[a].radius - s.particles[b].radius);
  return g;
}

}  // namespace

TEST(CaseFeatures, CappedCylinderHoldsItsBalls) {
  // A bore along x (radius 6 mm, length 40 mm) with 8 random balls of 4 mm (one layer fits on the
  // bottom); under gravity they fall to the bottom of the bore and none leaves (the run would stop
  // with exit 3 otherwise).
  CaseDir c(steel_scene("1 ms")
                .set("cavity", {{"kind", quoted("cylinder")}, {"material", quoted("steel")}, {"center", "[0, 0, 0]"},
                                {"axis", quoted("x")}, {"radius", "6 mm"}, {"length", "40 mm"}})
                .balls("balls", "steel", "4 mm", 8));
  const Scene s = load_case(c.str(), {"simulation.duration=\"60 ms\""});
  ASSERT_EQ(s.walls.size(), 3u);
  for (const auto& p : s.particles) {
    EXPECT_LE(std::hypot(p.x.y(), p.x.z()), 6e-3 - p.radius);
    EXPECT_LE(std::abs(p.x.x()), 20e-3 - p.radius);
  }
  EXPECT_GE(min_gap(s), 0.0);
  Simulation sim(s);
  while (sim.steps_done() < s.total_steps()) sim.step();
  // After 60 ms (a fall of up to 8 mm takes 40 ms) every ball is in the lower half of the bore.
  for (const auto& x : sim.particles().x) EXPECT_LT(x.z(), 0.0);
}

TEST(CaseFeatures, TableMotionFollowsTheTabulatedCurve) {
  // x(t) = A sin(2 pi f t) tabulated at 200 points a period; cubic Hermite with central slopes has
  // errors O(h^2) in velocity: with h = T/200 the position is within 1e-4 A, the velocity within
  // 1e-3 A w (reference: the analytic curve).
  const double A = 1e-3, f = 30, w = 2 * std::numbers::pi * f;
  std::string csv = "t,x,y,z\n";
  for (int k = 0; k <= 400; ++k) {
    const double t = k / (200.0 * f);
    char row[96];
    std::snprintf(row, sizeof row, "%.17g,%.17g,0,0\n", t, A * std::sin(w * t));
    csv += row;
  }
  CaseDir c(in_box()
                .set("cavity.motion", {{"kind", quoted("table")}, {"file", quoted("motion.csv")}})
                .balls("balls", "steel", "4 mm", 5));
  c.write("motion.csv", csv);
  const Scene s = load_case(c.str());
  for (double t = 0.001; t < 0.06; t += 0.0007) {
    const CavityState cs = s.motion->at(t);
    EXPECT_NEAR(cs.position.x(), A * std::sin(w * t), 1e-4 * A) << t;
    EXPECT_NEAR(cs.velocity.x(), A * w * std::cos(w * t), 1e-3 * A * w) << t;
  }
  // After the last row the cavity rests at the last position.
  EXPECT_EQ(s.motion->at(1.0).velocity.norm(), 0.0);
  EXPECT_NEAR(s.motion->max_speed(), A * w, 1e-2 * A * w);
}

TEST(CaseFeatures, TotalMassGivesTheNearestCount) {
  // 4-mm steel balls weigh 0.26138 g; 26.6 g is 101.77 balls -> 102.
  CaseDir c(in_box().set("particles.balls", {{"material", quoted("steel")}, {"diameter", "4 mm"}, {"total_mass", "26.6 g"},
                                            {"fill", quoted("lattice")}}));
  const Scene s = load_case(c.str());
  const double m = 7800 * std::numbers::pi / 6 * std::pow(4e-3, 3);
  EXPECT_EQ(s.particles.size(), static_cast<std::size_t>(std::lround(26.6e-3 / m)));
  EXPECT_GE(min_gap(s), 0.0);
}

TEST(CaseFeatures, SizeDistributionIsReproducibleAndOverlapFree) {
  const std::string toml = in_box()
                               .set("particles.balls", {{"material", quoted("steel")}, {"count", 150}})
                               .set("particles.balls.diameter_distribution",
                                    {{"kind", quoted("uniform")}, {"min", "3 mm"}, {"max", "5 mm"}});
  CaseDir c(toml);
  const Scene a = load_case(c.str()), b = load_case(c.str());
  const Scene other = load_case(c.str(), {"particles.balls.seed=99"});
  double mean = 0;
  for (const auto& p : a.particles) {
    EXPECT_GE(2 * p.radius, 3e-3);
    EXPECT_LE(2 * p.radius, 5e-3);
    mean += 2 * p.radius / static_cast<double>(a.particles.size());
  }
  EXPECT_NEAR(mean, 4e-3, 0.15e-3);  // uniform mean 4 mm, standard error 0.047 mm for 150 draws
  EXPECT_GE(min_gap(a), 0.0);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t k = 0; k < a.particles.size(); ++k) EXPECT_EQ(a.particles[k].x, b.particles[k].x);
  EXPECT_NE(a.particles[0].x, other.particles[0].x);
}

TEST(CaseFeatures, CsvParticlesAreReadExactly) {
  CaseDir c(in_box().set("particles.balls", {{"material", quoted("steel")}, {"file", quoted("balls.csv")}}));
  c.write("balls.csv", "x,y,z,diameter,vx,vy,vz\n0.005,0.005,0.005,0.004,0.1,0,-0.2\n0.015,0.005,0.005,0.004,0,0,0\n");
  const Scene s = load_case(c.str());
  ASSERT_EQ(s.particles.size(), 2u);
  EXPECT_EQ(s.particles[0].x, Vec3(0.005, 0.005, 0.005));
  EXPECT_EQ(s.particles[0].v, Vec3(0.1, 0, -0.2));
  EXPECT_EQ(s.particles[1].radius, 0.002);
}

// A file the case reads is part of the case: its fingerprint ends the resolved text (which a resume,
// a study's points and the commands reading results.h5 compare), the differences name it, and a
// map's damper record holds it. Before, an edited particle file or modal table left the case "the
// same", and a sweep resumed with it mixed two sets of balls or two structures in one table.
TEST(CaseFeatures, AnEditedFileTheCaseReadsIsAChangedCase) {
  CaseDir c(in_box().set("particles.balls", {{"material", quoted("steel")}, {"file", quoted("balls.csv")}}));
  const std::string csv = "x,y,z,diameter\n0.005,0.005,0.005,0.004\n0.015,0.005,0.005,0.004\n";
  c.write("balls.csv", csv);
  const Scene a = load_case(c.str());
  EXPECT_NE(a.resolved.find("# reads particles.balls.file = fnv1a64 "), std::string::npos) << a.resolved;
  c.write("balls.csv", csv);  // the same bytes written again: the same case
  EXPECT_EQ(load_case(c.str()).resolved, a.resolved);
  EXPECT_EQ(case_differences(a.resolved, a.resolved), "");

  c.write("balls.csv", "x,y,z,diameter\n0.005,0.005,0.005,0.003\n0.015,0.005,0.005,0.004\n");  // one ball smaller
  const Scene b = load_case(c.str());
  EXPECT_NE(b.resolved, a.resolved);
  const std::string diff = case_differences(a.resolved, b.resolved);
  EXPECT_NE(diff.find("the file at particles.balls.file: was fnv1a64"), std::string::npos) << diff;
  EXPECT_NE(diff.find("edited"), std::string::npos) << diff;
  const study::DamperRecord ra = study::damper_record(a), rb = study::damper_record(b);
  ASSERT_TRUE(ra.count("file.particles.balls.file"));
  EXPECT_FALSE(study::damper_differences(ra, rb).empty());
  // A resolved text of a bagdem before the fingerprints (no "# reads" line) differs too: it cannot tell.
  const std::string old = a.resolved.substr(0, a.resolved.find("\n# reads"));
  EXPECT_NE(case_differences(old, a.resolved).find("was not fingerprinted"), std::string::npos);
  // A directory at the key is bad input naming it (it was a library's read error, exit 1).
  std::filesystem::create_directories(c.path / "d");
  try {
    load_case(c.str(), {"particles.balls.file=\"d\""});
    ADD_FAILURE() << "a directory was read as a particle file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'particles.balls.file' = \"d\": names a directory"), std::string::npos) << e.what();
  }
}

// A file that a damper's keys name ([[dampers]], set) is the case's too: edited, the case differs.
TEST(CaseFeatures, AFileADamperReadsIsPartOfTheCase) {
  TempDir c;
  c.write("balls.csv", "x,y,z,diameter\n0.005,0.005,0.004,0.004\n0.012,0.005,0.004,0.004\n");
  c.write("b2.csv", "x,y,z,diameter\n0.005,0.005,0.004,0.004\n");
  c.write("case.toml", in_box()
                           .set("particles.balls", {{"material", quoted("steel")}, {"file", quoted("balls.csv")}})
                           .sdof("0.05 kg", "1776.5 N/m", 0.02)
                           .set("primary", "direction", "[1, 0, 0]")
                           .set("excitation", {{"kind", quoted("harmonic")}, {"amplitude", "0.05 N"}, {"frequency", "30 Hz"}})
                           .add("dampers", {{"name", quoted("two")}, {"set", "['particles.balls.file = \"b2.csv\"']"}}));
  const Scene a = load_case(c.str());
  EXPECT_NE(a.resolved.find("# reads dampers.two.particles.balls.file = fnv1a64 "), std::string::npos) << a.resolved;
  c.write("b2.csv", "x,y,z,diameter\n0.006,0.005,0.004,0.004\n");
  const std::string diff = case_differences(a.resolved, load_case(c.str()).resolved);
  EXPECT_NE(diff.find("the file at dampers.two.particles.balls.file"), std::string::npos) << diff;
}

// A particle file may be gzip-compressed (read in-process through zlib): the same particles as the
// plain file; a truncated stream is bad input naming the key and the file.
TEST(CaseFeatures, GzippedParticleFilesReadAsThePlainOnesAndATruncatedOneIsRefused) {
  const std::string csv = "x,y,z,diameter,vx,vy,vz\n0.005,0.005,0.005,0.004,0.1,0,-0.2\n0.015,0.005,0.005,0.004,0,0,0\n";
  const std::string data = "bed\n\n2 atoms\n1 atom types\n\nAtoms\n\n1 1 0.004 7800 0.005 0.005 0.005\n2 1 0.004 7800 0.015 0.005 0.005\n"
                           "\nVelocities\n\n1 0.1 0 -0.2 0 0 0\n2 0 0 0 0 0 0\n";
  for (const auto& [text, format] : {std::pair{csv, "csv"}, std::pair{data, "lammps-data"}}) {
    CaseDir c(in_box().set("particles.balls", {{"material", quoted("steel")}, {"file", quoted("balls.gz")}, {"format", quoted(format)}}));
    const std::string gz = c.str() + "/balls.gz";
    gzFile f = gzopen(gz.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(gzwrite(f, text.data(), static_cast<unsigned>(text.size())), static_cast<int>(text.size()));
    ASSERT_EQ(gzclose(f), Z_OK);
    ASSERT_NE(slurp(gz).substr(0, 2), text.substr(0, 2)) << "the file is compressed";
    const Scene s = load_case(c.str());
    ASSERT_EQ(s.particles.size(), 2u) << format;
    EXPECT_EQ(s.particles[0].x, Vec3(0.005, 0.005, 0.005));
    EXPECT_EQ(s.particles[0].v, Vec3(0.1, 0, -0.2));
    EXPECT_EQ(s.particles[1].radius, 0.002);

    const std::string whole = slurp(gz);
    std::ofstream(gz, std::ios::binary | std::ios::trunc) << whole.substr(0, whole.size() - 12);  // the trailer cut
    try {
      load_case(c.str());
      ADD_FAILURE() << format << ": a truncated gzip file was read";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("particles.balls.file"), std::string::npos) << m;
      EXPECT_NE(m.find("balls.gz"), std::string::npos) << m;
    }
  }
}

// A LAMMPS data file whose Atoms section holds fewer atoms than its header declares (a truncated
// file, as `head` makes one) is refused, and so is a CSV without a particle; both used to load the
// particles that were there.
TEST(CaseFeatures, ATruncatedParticleFileIsRefused) {
  const std::string data = "bed\n\n3 atoms\n1 atom types\n\nAtoms\n\n1 1 0.004 7800 0.005 0.005 0.005\n2 1 0.004 7800 0.015 0.005 0.005\n";
  for (const auto& [text, format, says] : {std::tuple{data, "lammps-data", "declares 3 atoms in its header but its Atoms section holds 2"},
                                           std::tuple{std::string("x,y,z,diameter\n"), "csv", "holds no particles"}}) {
    CaseDir c(in_box().set("particles.balls", {{"material", quoted("steel")}, {"file", quoted("balls.txt")}, {"format", quoted(format)}}));
    c.write("balls.txt", text);
    try {
      load_case(c.str());
      ADD_FAILURE() << format << ": loaded";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("particles.balls.file"), std::string::npos) << m;
      EXPECT_NE(m.find(says), std::string::npos) << m;
    }
  }
}
