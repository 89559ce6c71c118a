// Several dampers on one structure (case key [[dampers]], src/case/dampers.cpp, step/dampers.hpp):
//  - the keys, and the refusals of a damper that would change what the dampers share;
//  - one structure: each damper's mass matrix carries every cavity's mass (two cavities at one point
//    weigh as one with both masses);
//  - two-way coupling with every damper: the work the contents' load does on the beam is the work
//    all the dampers' walls do on their contents (exact for cavities that translate), and each
//    damper's share is large;
//  - the same bits on 1 and 2 threads, and twin dampers at one point stay twins bit for bit.
// The structure suite's soft balls in a box on a pinned-pinned beam (structure_cases.hpp).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "bagdem/reduce/compare.hpp"
#include "bagdem/run/runner.hpp"
#include "bagdem/run/stepped_sine.hpp"
#include "bagdem/step/dampers.hpp"
#include "structure_cases.hpp"

using namespace bagdem;
using bagdem::testing::TempDir;
using namespace bagdem::testing::structure_cases;

namespace {

// The beam driven near mode 1 (5 Hz) from its bare steady state, its first damper at x_b = 0.5 m;
// `dampers`: [[dampers]] tables.
std::string two_dampers(const std::string& dampers, const std::string& primary_more = "follow_slope = false\n") {
  const std::string p = beam_keys(0.5, "damping_ratio = 0.05\n" + primary_more) +
                        "\n[excitation]\nkind = \"harmonic\"\namplitude = \"3 N\"\nfrequency = \"5 Hz\"\nstart = \"steady\"\n" + kBalls + "\n" + dampers;
  return case_text(p, "duration = \"0.3 s\"\nsettle = \"0.1 s\"");
}

const char* kSecondAt03 = "[[dampers]]\nset = ['primary.attach = 0.3']\n";

}  // namespace

TEST(DampersCase, KeysAreReadAndWhatTheDampersShareIsRefused) {
  TempDir d;
  const Scene s = load(d, two_dampers("[damper]\nname = \"middle\"\n\n[[dampers]]\nname = \"side\"\nset = ['primary.attach = 0.3', "
                                      "'primary.cavity_mass = \"0.1 kg\"']\n"));
  ASSERT_EQ(s.more_dampers.size(), 1u);
  EXPECT_EQ(s.damper_name, "middle");
  EXPECT_EQ(s.more_dampers[0].name, "side");
  const Primary &a = *s.primary, &b = *s.more_dampers[0].scene->primary;
  EXPECT_DOUBLE_EQ(a.attach, 0.5);
  EXPECT_DOUBLE_EQ(b.attach, 0.3);
  EXPECT_TRUE(a.mass == b.mass);  // one structure
  EXPECT_EQ(s.more_dampers[0].scene->dt, s.dt);
  EXPECT_NE(describe_scene(s).find("damper      side: attached at 0.3 m"), std::string::npos) << describe_scene(s);

  auto refused = [&](const std::string& text, const std::string& part) {
    const std::string e = input_error(d, text);
    EXPECT_NE(e.find(part), std::string::npos) << e;
  };
  refused(two_dampers("[[dampers]]\nset = ['excitation.amplitude = \"1 N\"']\n"), "are the case's, shared");
  refused(two_dampers("[[dampers]]\nset = ['simulation.timestep = 1e-5']\n"), "dampers.0.set.0");
  refused(two_dampers("[[dampers]]\nset = []\n"), "dampers.0.set");
  refused(two_dampers("[[dampers]]\nset = ['primary.attach']\n"), "KEY = VALUE");
  refused(two_dampers("[[dampers]]\nname = \"1\"\nset = ['primary.attach = 0.3']\n"), "the name of another damper");
  refused(two_dampers("[[dampers]]\nname = \"a b\"\nset = ['primary.attach = 0.3']\n"), "OUT/dampers/NAME");
  refused(two_dampers("[[dampers]]\nset = ['primary.attach = 2']\n"), "damper '2' (dampers.0.set): ");
  refused(two_dampers("[[dampers]]\nset = ['primary.attach = 0.3']\nsize = 3\n"), "dampers.0.size");
  // Names name directories: no "..", no odd characters, not too long, the case's own too.
  for (const std::string& bad : {std::string(".."), std::string("."), std::string("a*b"), std::string("a/b"), std::string(65, 'n')})
    refused(two_dampers("[[dampers]]\nname = \"" + bad + "\"\nset = ['primary.attach = 0.3']\n"), "OUT/dampers/NAME");
  refused(two_dampers("[damper]\nname = \"a b\"\n" + std::string(kSecondAt03)), "damper.name");
  refused(two_dampers("[damper]\nname = \"2\"\n" + std::string(kSecondAt03)), "its default, \"2\" (its place), is another damper's name");
  // An orientation turns the structure's directions and gravity together.
  refused(two_dampers("[[dampers]]\nset = ['primary.direction = [0, 0, 1]']\n"), "are not the case's turned");
  EXPECT_EQ(input_error(d, two_dampers("[[dampers]]\nset = ['primary.direction = [0, 0, 1]', 'simulation.gravity = [0, \"9.81 m/s^2\", 0]']\n")),
            "(accepted)");
  // Prescribed motion: nothing to share.
  refused(case_text(std::string("[cavity.motion]\nkind = \"harmonic\"\namplitude = \"1 mm\"\nfrequency = \"5 Hz\"\n") + kBalls + kSecondAt03),
          "several dampers share one structure");
}

// Two cavities at one point weigh on the structure as one carrying both masses.
TEST(DampersCase, EveryCavitysMassIsInTheStructure) {
  TempDir d;
  const Scene two = load(d, two_dampers("[[dampers]]\nset = ['primary.cavity_mass = \"0.2 kg\"']\n", "cavity_mass = \"0.1 kg\"\n"));
  const Scene one = load(d, two_dampers("", "cavity_mass = \"0.3 kg\"\n"));
  EXPECT_LT((two.primary->mass - one.primary->mass).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((two.more_dampers[0].scene->primary->mass - one.primary->mass).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_GT((two.primary->mass - Eigen::MatrixXd::Identity(6, 6)).cwiseAbs().maxCoeff(), 0.1);  // the masses are there
}

// The work of the contents' load on the beam is that of every damper's walls on its contents: the
// cavities translate (follow_slope = false), so the two match to the rounding (one damper alone:
// test_structure.cpp, WallsWorkMatchesTheLoadsProjection). Leaving the second damper's load out
// would miss its share, which is a third or more here.
TEST(DampersCoupled, TheStructureFeelsEveryDamper) {
  TempDir d;
  const Scene s = load(d, two_dampers(kSecondAt03));
  Dampers sim(s);
  sim.advance(s.total_steps());
  const double load = sim[0].structure().scalars.work_contents;
  const double w0 = sim[0].energy().work_cavity, w1 = sim[1].energy().work_cavity;
  std::printf("  work of the walls on the contents: damper 1 %.6e J, damper 2 %.6e J; of the load on the beam %.6e J\n", w0, w1, load);
  EXPECT_LT(std::abs(load + w0 + w1), 1e-6 * (std::abs(w0) + std::abs(w1)));
  EXPECT_GT(std::abs(w1), 0.3 * std::abs(w0));
  EXPECT_TRUE(sim[0].structure().q == sim[1].structure().q);  // one structure, the same bits in each
}

// The same bits on 1 and 2 threads; twin dampers (the same contents at the same point) stay twins.
TEST(DampersCoupled, SameBitsOnAnyThreadsAndTwinsStayTwins) {
  TempDir d;
  const Scene s = load(d, two_dampers("[[dampers]]\nset = ['primary.attach = 0.5']\n"), {"simulation.settle=0.01"});
  auto run = [&](int threads) {
    const int was = omp_get_max_threads();
    omp_set_num_threads(threads);
    Dampers sim(s);
    sim.set_parallel(true);  // 12 balls a damper: side by side only when asked
    sim.advance(1500);
    sim.advance(1500);
    EXPECT_GT(sim.time(), 1.5 * s.settle);  // the structure moves
    omp_set_num_threads(was);
    return sim.save_state();
  };
  const auto one = run(1), two = run(2);
  EXPECT_TRUE(one == two);
  EXPECT_TRUE(one[0] == one[1]);
}

// `bagdem run` of two dampers: the case's own in OUT with the structure's table, the other in
// OUT/dampers/NAME with its own record; a run killed half way and resumed ends with the same
// figures for both as one that was not; a later run of one damper takes the other's directory away.
TEST(DampersRun, EachDamperIsRecordedAndAResumeEndsTheSame) {
  TempDir d;
  const Scene s = load(d, two_dampers("[[dampers]]\nname = \"side\"\nset = ['primary.attach = 0.3']\n"), {"output.checkpoint_interval=0.05"});
  const RunReport a = run_scene(s, bagdem::testing::quiet_run(d.path / "whole", 2));
  ASSERT_TRUE(a.complete) << a.message;
  ASSERT_EQ(a.dampers.size(), 1u);
  EXPECT_EQ(a.dampers[0].name, "side");
  const auto whole = [&](const std::string& f) { return bagdem::testing::slurp(d.path / "whole" / f); };
  const auto side = [&](const std::string& f) { return bagdem::testing::slurp(d.path / "whole" / "dampers" / "side" / f); };
  EXPECT_NE(whole("summary.json").find("\"structure\""), std::string::npos);
  EXPECT_EQ(side("summary.json").find("\"structure\""), std::string::npos);  // the structure once
  EXPECT_NE(side("summary.json").find("\"damper\": \"side\""), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(d.path / "whole" / "dampers" / "side" / "results.h5"));

  const Scene one = load(d, two_dampers(""));
  RunOptions cut = bagdem::testing::quiet_run(d.path / "cut", 1, static_cast<long long>(0.25 / s.dt));
  EXPECT_FALSE(run_scene(s, cut).complete);
  cut.stop_after_steps = -1, cut.resume = true;
  const RunReport b = run_scene(s, cut);
  ASSERT_TRUE(b.complete) << b.message;
  // The energy figures of both dampers and the structure's, digit for digit (summary.json's "energy" and "structure").
  auto figures = [](const std::string& json) { return json.substr(json.find("\"energy\": {"), json.find("\"cycles_measured\"") - json.find("\"energy\": {")); };
  const auto cut_file = [&](const std::string& f) { return bagdem::testing::slurp(d.path / "cut" / f); };
  EXPECT_EQ(figures(cut_file("summary.json")), figures(whole("summary.json")));
  EXPECT_EQ(figures(cut_file("dampers/side/summary.json")), figures(side("summary.json")));

  // A later run of one damper takes away what bagdem wrote for the other, and nothing else.
  std::filesystem::create_directories(d.path / "whole" / "dampers" / "mine");
  d.write("whole/dampers/mine/notes.txt", "kept");
  ASSERT_TRUE(run_scene(one, bagdem::testing::quiet_run(d.path / "whole", 1)).complete);
  EXPECT_FALSE(std::filesystem::exists(d.path / "whole" / "dampers" / "side"));
  EXPECT_EQ(bagdem::testing::slurp(d.path / "whole" / "dampers" / "mine" / "notes.txt"), "kept");
}

// Each damper's checkpoint is its own file: dampers checkpointed at different steps (a run stopped
// between two writes) are refused, not run on as one run.
TEST(DampersRun, CheckpointsOfDifferentStepsAreRefused) {
  TempDir d;
  const Scene s = load(d, two_dampers("[[dampers]]\nname = \"side\"\nset = ['primary.attach = 0.3']\n"), {"output.checkpoint_interval=0.05"});
  RunOptions o = bagdem::testing::quiet_run(d.path / "out", 1, static_cast<long long>(0.12 / s.dt));
  ASSERT_FALSE(run_scene(s, o).complete);
  const auto side = d.path / "out" / "dampers" / "side" / "checkpoint.bin";
  std::filesystem::copy_file(side, d.path / "older.bin");
  o.resume = true, o.stop_after_steps = static_cast<long long>(0.12 / s.dt);
  ASSERT_FALSE(run_scene(s, o).complete);
  std::filesystem::copy_file(d.path / "older.bin", side, std::filesystem::copy_options::overwrite_existing);
  o.stop_after_steps = -1;
  try {
    run_scene(s, o);
    ADD_FAILURE() << "resumed dampers of different steps";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("damper side's checkpoint is of step"), std::string::npos) << e.what();
  }
}

// A guard that stops one damper's run stops the run, naming the damper; each damper's record is
// kept as results.failed.h5 (exit code 3 for `bagdem run`).
TEST(DampersRun, AFailingDamperStopsTheRunAndIsNamed) {
  TempDir d;
  d.write("case.toml", two_dampers("[[dampers]]\nname = \"limp\"\nset = ['materials.soft.youngs_modulus = \"2 kPa\"']\n"));
  const auto r = bagdem::testing::run_bagdem({"run", d.str(), "--out", (d.path / "out").string(), "--quiet", "--threads", "2"}, d.path);
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("damper limp: "), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::exists(d.path / "out" / "results.failed.h5"));
  EXPECT_TRUE(std::filesystem::exists(d.path / "out" / "dampers" / "limp" / "results.failed.h5"));
}

// Commands that run one damper refuse a case of several, saying which do (exit 2).
TEST(DampersRun, ACommandOfOneDamperRefusesSeveral) {
  TempDir d;
  d.write("case.toml", two_dampers(kSecondAt03));
  const auto r = bagdem::testing::run_bagdem({"drop", d.str(), "--out", (d.path / "out").string()}, d.path);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("this command runs one damper"), std::string::npos) << r.err;
}

// A coupled sweep of two dampers on an SDOF (the structure suite's energy-balance sweep with a
// second box of 8 balls): each point's energy balance closes over the structure and both dampers'
// contents (the second's dissipation is a fifth or more of the whole, so a ledger that left it out
// would miss by that much), each damper has its reduced rows (the other's in OUT/dampers/NAME), and
// 1 and 2 threads give the same tables.
TEST(DampersSweep, TheBalanceClosesOverEveryDamperAndEachIsReduced) {
  TempDir d;
  const double M = 0.25, fn = 12, zeta = 0.05, K = M * std::pow(2 * std::numbers::pi * fn, 2);
  std::ostringstream p;
  p << "[primary]\nkind = \"sdof\"\nmass = " << M << "\nstiffness = " << K << "\ndamping_ratio = " << zeta << "\n\n"
    << "[excitation]\nkind = \"stepped-sine\"\namplitude = \"0.5 N\"\nfrequencies = [\"11.5 Hz\", \"12 Hz\"]\n"
    << "steady_tolerance = 0.003\nsteady_cycles = 8\nmin_cycles = 16\nmax_cycles = 200\n" << kBalls
    << "\n[[dampers]]\nname = \"two\"\nset = ['particles.balls.count = 8']\n";
  const Scene s = load(d, case_text(p.str(), "duration = \"1 s\"\nsettle = \"0.2 s\""));
  const SteppedSineReport r = run_stepped_sine(s, bagdem::testing::quiet_run(d.path / "t2", 2));
  ASSERT_TRUE(r.complete) << r.message;
  ASSERT_EQ(r.points.size(), 2u);
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const SteppedSinePoint& pt = r.points[i];
    const double own = r.reduced[i].dissipated_per_cycle, other = pt.dissipated_contents - own;
    std::printf("  %.3f Hz: W_ext %.4e J/cycle = D_structure %.4e + D_contents %.4e (damper 1 %.4e, damper two %.4e); closure %.2e\n",
                pt.frequency, pt.work_external, pt.dissipated_structure, pt.dissipated_contents, own, other, pt.balance);
    EXPECT_LT(std::abs(pt.balance), 0.01);
    EXPECT_GT(other, 0.2 * pt.dissipated_contents);
    EXPECT_GT(own, 0.2 * pt.dissipated_contents);
    EXPECT_NEAR(pt.work_external, pt.dissipated_structure + pt.dissipated_contents, 0.03 * pt.work_external);
  }
  // The modal model with both dampers' measured impedances (compare.csv) follows the DEM; with the
  // first damper's alone it does not.
  const std::vector<CompareRow> alone = compare_with_continuum(*s.primary, s.primary->amplitude, r.reduced);
  ASSERT_EQ(r.compare.size(), r.points.size());
  double both = 0, first = 0;
  for (std::size_t i = 0; i < r.compare.size(); ++i) {
    std::printf("  %.3f Hz: DEM %.4e m, modal model with both dampers %.4e m (%+.1f%%), with the first alone %+.1f%%\n", r.compare[i].frequency,
                r.compare[i].dem_response, r.compare[i].model_response, 100 * r.compare[i].model_error, 100 * alone[i].model_error);
    both = std::max(both, std::abs(r.compare[i].model_error)), first = std::max(first, std::abs(alone[i].model_error));
  }
  EXPECT_LT(both, 0.05);
  EXPECT_GT(first, 3 * both);
  const auto table = [&](const std::string& run, const std::string& f) { return bagdem::testing::slurp(d.path / run / f); };
  const std::string two = table("t2", "dampers/two/reduced.csv"), own = table("t2", "reduced.csv");
  EXPECT_EQ(std::count(two.begin(), two.end(), '\n'), std::count(own.begin(), own.end(), '\n'));
  const SteppedSineReport one = run_stepped_sine(s, bagdem::testing::quiet_run(d.path / "t1", 1));
  ASSERT_TRUE(one.complete) << one.message;
  EXPECT_EQ(table("t1", "reduced.csv"), table("t2", "reduced.csv"));
  EXPECT_EQ(table("t1", "dampers/two/reduced.csv"), two);
  EXPECT_EQ(table("t1", "peaks.csv"), table("t2", "peaks.csv"));
  // One chain killed in its second point and resumed: the same tables as that chain run whole (the
  // other damper's rows and clearance come back from the checkpoint's block of them).
  const Scene chain = load(d, case_text(p.str(), "duration = \"1 s\"\nsettle = \"0.2 s\""), {"excitation.chains=1"});
  const SteppedSineReport whole = run_stepped_sine(chain, bagdem::testing::quiet_run(d.path / "t4", 1));
  ASSERT_TRUE(whole.complete) << whole.message;
  const double into = chain.settle + whole.points[0].cycles / whole.points[0].frequency + 0.5 * whole.points[1].cycles / whole.points[1].frequency;
  RunOptions cut = bagdem::testing::quiet_run(d.path / "t3", 1, static_cast<long long>(into / chain.dt));
  ASSERT_FALSE(run_stepped_sine(chain, cut).complete);
  ASSERT_TRUE(std::filesystem::exists(d.path / "t3" / "dampers" / "two" / "reduced.partial.csv"));  // the first point was written
  ASSERT_FALSE(std::filesystem::exists(d.path / "t3" / "dampers" / "two" / "reduced.csv"));
  cut.stop_after_steps = -1, cut.resume = true;
  ASSERT_TRUE(run_stepped_sine(chain, cut).complete);
  EXPECT_EQ(table("t3", "reduced.csv"), table("t4", "reduced.csv"));
  EXPECT_EQ(table("t3", "dampers/two/reduced.csv"), table("t4", "dampers/two/reduced.csv"));
  EXPECT_EQ(table("t3", "peaks.csv"), table("t4", "peaks.csv"));
}

// The shipped case of two bags resolves: both listed, the sweep without a predicted start.
TEST(DampersCase, TheShippedPairChecks) {
  TempDir d;
  const auto r = bagdem::testing::run_bagdem({"check", std::string(BAGDEM_CASES_DIR) + "/stepped-beam-pair"}, d.path);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("damper      mid: attached at 0.335 m"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("predicted with the contents"), std::string::npos) << r.out;
}

// The modal model's bags: two at one place are one with both masses and dashpots (to rounding).
TEST(DampersModel, TwoBagsAtOnePlaceAreOneWithBoth) {
  continuum::ModalModel m;
  m.omega = Eigen::Vector2d(2 * std::numbers::pi * 10, 2 * std::numbers::pi * 31);
  m.zeta = Eigen::Vector2d(0.01, 0.02);
  m.shape_at_force = Eigen::Vector2d(0.7, -0.4), m.shape_at_response = Eigen::Vector2d(0.9, 0.3);
  m.shape_at_bag = Eigen::Vector2d(0.5, 0.8);
  for (const double hz : {8.0, 10.0, 12.5, 31.0}) {
    const double w = 2 * std::numbers::pi * hz;
    const std::complex<double> one = continuum::modal_receptance(m, 0.3, 2.0, w);
    const std::complex<double> two = continuum::modal_receptance(m, {{m.shape_at_bag, 0.1, 0.5}, {m.shape_at_bag, 0.2, 1.5}}, w);
    EXPECT_LT(std::abs(two - one), 1e-12 * std::abs(one)) << hz << " Hz";
    EXPECT_EQ(continuum::modal_receptance(m, {{m.shape_at_bag, 0.3, 2.0}}, w), one);  // one bag: the same bits
  }
}
