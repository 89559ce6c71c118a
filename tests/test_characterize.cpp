// `bagdem characterize` (study/characterize.hpp):
// 1. Its grid: Gamma log-spaced, frequencies evenly over each band of a sweep (one band per mode),
//    X = Gamma g / w^2; bad ranges refused naming the option.
// 2. A cell's figures are the mean and the 95% interval of its starts (Student t, n - 1).
// 3. Through the binary, on an analytic reference: a solid steel ball resting on the floor of a
//    box shaken horizontally below the sliding limit rolls without slip, so the floor's friction on
//    it is (2/7) m a (I = (2/5) m r^2) and it dissipates nothing: M_eff / m = 2/7, C_eff = 0. The
//    case is coupled (an SDOF primary): characterize drops it and prescribes the cavity's motion
//    along primary.direction. The map's files hold the grid and the figures; a second call resumes.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/bag/bag.hpp"
#include "bagdem/study/characterize.hpp"
#include "bagdem/study/damper_record.hpp"
#include "bagdem/io/table_csv.hpp"
#include "bagdem/study/study.hpp"
#include "case_texts.hpp"
#include "h5_read.hpp"
#include "support.hpp"

using namespace bagdem;
using namespace bagdem::study;
using bagdem::testing::CaseText;
namespace fs = std::filesystem;


TEST(CharacterizeGrid, GammaLogSpacedFrequenciesPerBandAmplitudeFromGamma) {
  const auto bands = stepped_sine_bands({80, 77, 83, 86, 470, 440, 455, 485, 89});
  ASSERT_EQ(bands.size(), 2u);
  EXPECT_EQ(bands[0], std::make_pair(77.0, 89.0));
  EXPECT_EQ(bands[1], std::make_pair(440.0, 485.0));
  EXPECT_EQ(stepped_sine_bands({10, 20, 30, 40}).size(), 1u);

  bagdem::testing::TempDir t;
  std::ofstream(t.path / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  const Scene s = load_case(t.path.string());
  CharacterizeArgs a;
  a.amplitudes = 3, a.frequencies = 3, a.gamma = {0.5, 2};
  const MapPlan g = map_plan(s, a);
  ASSERT_EQ(g.axes.gamma.size(), 3u);
  EXPECT_NEAR(g.axes.gamma[1], 1.0, 1e-12);
  ASSERT_EQ(g.axes.frequency.size(), 3u);
  EXPECT_NEAR(g.axes.frequency[0], 18, 1e-12);
  EXPECT_NEAR(g.axes.frequency[1], 20, 1e-12);
  EXPECT_NEAR(g.axes.frequency[2], 22, 1e-12);
  EXPECT_NEAR(g.axes.g, 9.81, 1e-12);
  EXPECT_NEAR(g.amplitude(2, 1), 2 * 9.81 / std::pow(2 * std::numbers::pi * 20, 2), 1e-15);
  EXPECT_EQ(g.direction, Vec3::UnitX());

  for (auto bad : {std::vector<double>{2, 0.5}, std::vector<double>{0, 1}, std::vector<double>{1}}) {
    CharacterizeArgs b = a;
    b.gamma = bad;
    try {
      map_plan(s, b);
      ADD_FAILURE() << "accepted --gamma of " << bad.size() << " values";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--gamma"), std::string::npos) << e.what();
    }
  }
  CharacterizeArgs one = a;
  one.amplitudes = 1;
  EXPECT_THROW(map_plan(s, one), InputError);
}

TEST(CharacterizeGrid, ARunLastsAtLeastTheCyclesAndTheTimeAsked) {
  CharacterizeArgs a;  // 5 + 20 cycles, 0.1 + 0.25 s
  EXPECT_EQ(run_cycles(a, 20), std::make_pair(5, 20));     // 0.25 + 1 s: the counts rule at a low frequency
  EXPECT_EQ(run_cycles(a, 85), std::make_pair(9, 22));     // 0.1 s is 8.5 cycles, 0.25 s 21.25
  EXPECT_EQ(run_cycles(a, 480), std::make_pair(48, 120));  // whole up to rounding: not 49 and 121
  a.skip_time = a.window_time = 0;
  EXPECT_EQ(run_cycles(a, 480), std::make_pair(5, 20));
}

TEST(CharacterizeGrid, ACellIsTheMeanOfItsStartsWithTheirStudentInterval) {
  std::vector<ReducedRow> rows(3);
  for (int k = 0; k < 3; ++k) {
    rows[k].M_eff = 1 + k;  // 1, 2, 3: mean 2, sd 1
    rows[k].C_eff = 5;
    rows[k].e = k == 1 ? ReducedRow::kUnknown : 0.5;
    rows[k].e_method = k == 1 ? "none" : "impact";
  }
  const MapCell c = map_cell(1, 20, 1e-3, rows);
  EXPECT_EQ(c.starts, 3u);
  EXPECT_EQ(c.steady, 3u);
  EXPECT_NEAR(c.M_eff.mean, 2, 1e-15);
  EXPECT_NEAR(c.M_eff.ci95, 4.302653 / std::sqrt(3.0), 1e-4);  // t_{0.975, 2} to 4 decimals
  EXPECT_NEAR(c.C_eff.ci95, 0, 1e-15);
  EXPECT_EQ(c.e_starts, 2u);  // the start without an e is left out of e's figure
  EXPECT_NEAR(c.e.mean, 0.5, 1e-15);
  EXPECT_EQ(c.e_method, "impact");
  rows[2].e_method = "eq19a";
  EXPECT_EQ(map_cell(1, 20, 1e-3, rows).e_method, "mixed");
  // An unsteady start is counted and left out of the figures.
  rows[2].steady = 0;
  const MapCell u = map_cell(1, 20, 1e-3, rows);
  EXPECT_EQ(u.starts, 3u);
  EXPECT_EQ(u.steady, 2u);
  EXPECT_NEAR(u.M_eff.mean, 1.5, 1e-15);
  EXPECT_EQ(u.M_eff.repeats, 2u);
}

TEST(Characterize, ABallRollingOnAShakenFloorWeighsTwoSeventhsAndDissipatesNothing) {
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << bagdem::testing::ball_on_sdof_floor();
  const fs::path out = t.path / "map";
  const std::vector<std::string> args = {"characterize", dir.string(), "--gamma", "0.1,0.4", "--amplitudes", "2", "--frequencies", "2",
                                         "--seeds", "2", "--cycles", "6", "--skip", "2", "--out", out.string(), "--jobs", "2"};
  const bagdem::testing::CmdResult r = bagdem::testing::run_bagdem(args, t.path);
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("map: 2 amplitudes x 2 frequencies"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("characterize: 8 done"), std::string::npos) << "the progress names the command (it said sweep:)\n" << r.err;
  EXPECT_EQ(r.err.find("sweep:"), std::string::npos) << r.err;

  const TextTable m = read_text_table(out / "map.csv");
  ASSERT_EQ(m.rows.size(), 4u);
  const std::size_t gamma = m.find("gamma"), freq = m.find("frequency"), amp = m.find("amplitude"), starts = m.find("starts"),
                    ratio = m.find("M_eff_ratio"), cb = m.find("Cb_over_Mbw"), measured = m.find("gamma_measured");
  ASSERT_LT(std::max({gamma, freq, amp, starts, ratio, cb, measured}), m.names.size());
  EXPECT_EQ(m.units[m.find("C_eff")], "N s/m");
  EXPECT_LT(m.find("C_eff_ci95"), m.names.size());
  ASSERT_LT(m.find("e_method"), m.names.size());
  for (const auto& row : m.rows) {
    const double G = std::stod(row[gamma]), f = std::stod(row[freq]);
    std::printf("  Gamma %.2f at %.0f Hz: M_eff / m %.5f (2/7 = %.5f), C_b / (M_b w) %.2e\n", G, f, std::stod(row[ratio]), 2.0 / 7.0,
                std::stod(row[cb]));
    EXPECT_NEAR(std::stod(row[amp]), G * 9.81 / std::pow(2 * std::numbers::pi * f, 2), 1e-9 * std::stod(row[amp]));
    EXPECT_EQ(row[starts], "2");
    EXPECT_NE(row[m.find("e_method")], "mixed") << "the starts are the same start (the ball's place is given)";
    EXPECT_NEAR(std::stod(row[measured]), G, 0.01 * G) << "the cavity moved as asked";
    EXPECT_NEAR(std::stod(row[ratio]), 2.0 / 7.0, 1e-3 * 2.0 / 7.0) << "rolling without slip at Gamma " << G << ", " << f << " Hz";
    EXPECT_LT(std::abs(std::stod(row[cb])), 1e-4) << "no slip, no dissipation";
  }
  // map.h5: the figures on the grid [amplitudes x frequencies].
  const hid_t h = bagdem::testing::open_read((out / "map.h5").string());
  ASSERT_GE(h, 0);
  const auto ratio_h5 = bagdem::testing::read_doubles(h, "M_eff_ratio/mean");
  EXPECT_EQ(ratio_h5.dims, (std::vector<hsize_t>{2, 2}));
  ASSERT_EQ(ratio_h5.values.size(), 4u);
  for (double x : ratio_h5.values) EXPECT_NEAR(x, 2.0 / 7.0, 0.01 * 2.0 / 7.0);
  EXPECT_EQ(bagdem::testing::unit_of(h, "C_eff/mean"), "N s/m");
  EXPECT_EQ(bagdem::testing::read_doubles(h, "gamma").values.size(), 2u);
  H5Fclose(h);
  const std::string js = bagdem::testing::slurp(out / "map.json");
  EXPECT_NE(js.find("\"Cb_over_Mbw\": {\"unit\": \"1\", \"mean\": [["), std::string::npos) << js;

  // Again: every run is done, nothing runs, the map is the same.
  const std::string before = bagdem::testing::slurp(out / "map.csv");
  const bagdem::testing::CmdResult again = bagdem::testing::run_bagdem(args, t.path);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("resum"), std::string::npos) << again.err;
  EXPECT_EQ(bagdem::testing::slurp(out / "map.csv"), before);

  // The map records its damper (damper.toml), and predict refuses a case whose damper differs,
  // naming the keys; the structure, the drive and where the damper sits are not the damper's.
  // (predict used to print a figure for any case with any map.)
  EXPECT_NE(bagdem::testing::slurp(out / "damper.toml").find("'particles.ball.diameter' = '0.01'"), std::string::npos)
      << bagdem::testing::slurp(out / "damper.toml");
  auto predict = [&](const std::vector<std::string>& sets) {
    // Near the peak at 0.1 N the cavity's amplitude lies within the map's Gamma.
    std::vector<std::string> p = {"predict", dir.string(), "--map", out.string(), "--out", (t.path / "p").string(), "--amplitude", "0.1 N",
                                  "--set", "excitation.frequencies=[19.8, 20, 20.2]"};
    for (const std::string& x : sets) p.insert(p.end(), {"--set", x});
    return bagdem::testing::run_bagdem(p, t.path);
  };
  for (const auto& sets : {std::vector<std::string>{}, {"primary.damping_ratio=0.021", "excitation.amplitude=\"1 mN\""}}) {
    const auto same = predict(sets);
    EXPECT_EQ(same.code, 0) << same.err << same.out;
    EXPECT_EQ(same.err.find("records no damper"), std::string::npos) << same.err;
  }
  struct Other {
    std::string set, expect;
  };
  // characterize into that map with another damper: refused before anything runs, the map as it was.
  {
    std::vector<std::string> other = args;
    other.insert(other.end(), {"--set", "particles.ball.diameter=\"8 mm\""});
    const auto r = bagdem::testing::run_bagdem(other, t.path);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("holds the runs of another damper (particles.ball.diameter is 0.01 in the map, 0.008 in the case)"), std::string::npos) << r.err;
    EXPECT_EQ(bagdem::testing::slurp(out / "map.csv"), before);
  }
  for (const Other& o : {Other{"particles.ball.diameter=\"8 mm\"", "particles.ball.diameter is 0.01 in the map, 0.008 in the case"},
                         Other{"cavity.max=[\"20 mm\", \"12 mm\", \"10 mm\"]", "cavity.max is [0.02, 0.01, 0.01] in the map, [0.02, 0.012, 0.01]"},
                         Other{"interactions.default.friction=0.5", "(the law of steel on steel, from [interactions] and [materials]): mu_s 0.3 in the map, mu_s 0.5 in the case"}}) {
    const auto r = predict({o.set});
    EXPECT_EQ(r.code, 2) << o.set << ": " << r.err << r.out;
    EXPECT_NE(r.err.find("characterised another damper than the case's"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(o.expect), std::string::npos) << o.expect << " not in: " << r.err;
  }
  // map.csv changed after characterize wrote it (one digit of a figure): refused, naming the file
  // and damper.toml's fingerprint (a C_eff x 1.2 by hand gave another figure, exit 0); as written
  // again, predicted again.
  EXPECT_NE(bagdem::testing::slurp(out / "damper.toml").find("bands = [ [ "), std::string::npos) << bagdem::testing::slurp(out / "damper.toml");
  std::string text = before;
  text[text.rfind('1')] = '2';
  std::ofstream(out / "map.csv") << text;
  const auto edited = predict({});
  EXPECT_EQ(edited.code, 2) << edited.err << edited.out;
  EXPECT_NE(edited.err.find("is not the map.csv bagdem characterize wrote"), std::string::npos) << edited.err;
  std::ofstream(out / "map.csv") << before;
  EXPECT_EQ(predict({}).code, 0);
}

TEST(Characterize, RefusesACaseWithoutABandOrADirection) {
  bagdem::testing::TempDir t;
  const fs::path dir = t.path / "case";
  fs::create_directories(dir);
  std::ofstream(dir / "case.toml") << CaseText()
                                          .simulation("0.1 s")
                                          .steel("2 GPa")
                                          .interactions(0.5, 0.3)
                                          .box("steel", "[-0.01, -0.01, -0.01]", "[0.01, 0.01, 0.01]")
                                          .placed("ball", "steel", "4 mm", "[[0, 0, 0]]")
                                          .str();
  const auto r = bagdem::testing::run_bagdem({"characterize", dir.string(), "--out", (t.path / "m").string()}, t.path);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--band"), std::string::npos) << r.err;
  const auto r2 = bagdem::testing::run_bagdem({"characterize", dir.string(), "--band", "20,40", "--out", (t.path / "m").string()}, t.path);
  EXPECT_EQ(r2.code, 2) << r2.err;
  EXPECT_NE(r2.err.find("direction"), std::string::npos) << r2.err;
  EXPECT_FALSE(fs::exists(t.path / "m" / "map.csv"));
}

// A map's damper.toml records the damper's resolved model choices: the film's (model.film.*) and
// the law of each pair of its materials (model.pair.A/B), none of them depending on the seed. So a
// bagdem whose film default differs (here the bending stiffness, the case's text the same) finds the
// map stale, naming the choice, and so does a map recorded before them.
// A material is named, never read as a quantity: one named "4mm" keeps its properties in the record
// (they were dropped, "4mm" recorded as 0.004, and a map served balls of another modulus).
TEST(Characterize, TheDamperRecordNamesAMaterialNamedLikeAQuantity) {
  bagdem::testing::TempDir t;
  const std::string pipe = std::string(BAGDEM_SOURCE_DIR) + "/cases/pipe-beanbag";
  fs::create_directories(t.path / "case");
  for (const auto& e : fs::directory_iterator(pipe))
    if (e.is_regular_file()) fs::copy_file(e.path(), t.path / "case" / e.path().filename());
  std::string text = bagdem::testing::slurp(t.path / "case" / "case.toml");
  for (std::size_t at; (at = text.find("steel")) != std::string::npos;) text.replace(at, 5, "4mm");
  std::ofstream(t.path / "case" / "case.toml") << text;
  const std::string dir = (t.path / "case").string();
  const bagdem::study::DamperRecord made = bagdem::study::damper_record(bagdem::load_case(dir));
  EXPECT_EQ(made.at("bag.balls.material"), "4mm");
  EXPECT_TRUE(made.count("materials.4mm.youngs_modulus") && made.count("model.pair.4mm/ldpe"));
  const std::vector<std::string> diff =
      bagdem::study::damper_differences(made, bagdem::study::damper_record(bagdem::load_case(dir, {"materials.4mm.youngs_modulus=\"200 GPa\""})));
  ASSERT_FALSE(diff.empty());
  EXPECT_NE(diff[0].find("materials.4mm.youngs_modulus"), std::string::npos) << diff[0];
}

// One damper said in other words is the same damper: a pair's table named b-a for a-b, a law given
// at its default, a pair of a material the damper does not use, an axis as "x" or as any vector
// along x, the bag's strings in another order. A change of any of them is another damper.
TEST(Characterize, OneDamperSaidOtherwiseIsTheSameDamper) {
  namespace st = bagdem::study;
  const std::string pipe = std::string(BAGDEM_SOURCE_DIR) + "/cases/pipe-beanbag";
  const st::DamperRecord made = st::damper_record(bagdem::load_case(pipe));
  const std::string tail = R"({at = "tail", anchor = ["-35 mm", "0 mm", "0 mm"], stiffness = "200 N/m", damping = "0.05 N s/m"})",
                    head = R"({at = "head", anchor = ["35 mm", "0 mm", "0 mm"], stiffness = "200 N/m", damping = "0.05 N s/m"})";
  // The pair's table of the balls on the film named ldpe-steel (its restitution 0.35: another damper).
  std::string text = bagdem::testing::slurp(pipe + "/case.toml");
  const std::size_t at = text.find("[interactions.steel-ldpe]");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 25, "[interactions.ldpe-steel]");
  const bagdem::testing::TempDir renamed, changed;
  renamed.write("case.toml", text);
  const std::size_t e = text.find("restitution = 0.3", at);
  ASSERT_NE(e, std::string::npos);
  changed.write("case.toml", text.replace(e, 17, "restitution = 0.35"));
  EXPECT_TRUE(st::damper_differences(made, st::damper_record(bagdem::load_case(renamed.str()))).empty());
  // A table for the pair under each name: refused (one would overwrite the other, unseen).
  try {
    bagdem::load_case(pipe, {"interactions.ldpe-steel.restitution=0.35"});
    ADD_FAILURE() << "two tables for one pair were taken";
  } catch (const bagdem::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'interactions.steel-ldpe'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("sets the pair steel-ldpe again (also [interactions.ldpe-steel]): give one table per pair"),
              std::string::npos) << e.what();
  }
  const std::vector<std::string> law = st::damper_differences(made, st::damper_record(bagdem::load_case(changed.str())));
  ASSERT_EQ(law.size(), 1u);
  EXPECT_EQ(law[0].rfind("model.pair.ldpe/steel (the law of ldpe on steel, from [interactions] and [materials]): e 0.3 in the map, e 0.35 in the case; damping ", 0), 0u)
      << law[0];
  const std::vector<std::vector<std::string>> same = {
      {"interactions.default.law=\"hertz-mindlin\""},
      {"materials.glass={density = \"2500 kg/m^3\", youngs_modulus = \"60 GPa\", poisson_ratio = 0.2}",
       "interactions.glass-steel={restitution = 0.9}"},
      {"cavity.axis=[1, 0, 0]"},
      {"cavity.axis=[2.5, 0, 0]"},
      {"bag.strings=[" + head + ", " + tail + "]"},
  };
  for (const std::vector<std::string>& sets : same) {
    SCOPED_TRACE(sets[0]);
    const st::DamperRecord other = st::damper_record(bagdem::load_case(pipe, sets));
    const std::vector<std::string> d = st::damper_differences(made, other), back = st::damper_differences(other, made);
    EXPECT_TRUE(d.empty()) << sets[0] << ": " << (d.empty() ? "" : d[0]);
    EXPECT_TRUE(back.empty()) << sets[0] << ": " << (back.empty() ? "" : back[0]);
  }
  // A record written before this rule (with its [interactions] keys) is the same damper, and so is
  // an axis recorded at its default.
  st::DamperRecord older = made;
  older["interactions.default.restitution"] = "0.5";
  older["interactions.steel-ldpe.restitution"] = "0.3";
  older["cavity.axis"] = "(default) [4, 0, 0]";
  EXPECT_TRUE(st::damper_differences(older, made).empty()) << st::damper_differences(older, made)[0];
  older["cavity.axis"] = "(default) [0, 0, 1]";
  ASSERT_EQ(st::damper_differences(older, made).size(), 1u);
  EXPECT_EQ(st::damper_differences(older, made)[0], "cavity.axis is [0, 0, 1] (the default) in the map, [1, 0, 0] in the case");
  const std::string stiffer = R"({at = "head", anchor = ["35 mm", "0 mm", "0 mm"], stiffness = "300 N/m", damping = "0.05 N s/m"})";
  const std::vector<std::pair<std::vector<std::string>, std::string>> other = {
      {{"cavity.axis=[1, 0.01, 0]"}, "cavity.axis is [1, 0, 0] in the map, [0.99995"},
      {{"bag.strings=[" + tail + ", " + stiffer + "]"}, "bag.strings.1.stiffness is 200 in the map, 300 in the case"},
  };
  for (const auto& [sets, said] : other) {
    const std::vector<std::string> d = st::damper_differences(made, st::damper_record(bagdem::load_case(pipe, sets)));
    ASSERT_FALSE(d.empty()) << sets[0];
    EXPECT_EQ(d[0].rfind(said, 0), 0u) << d[0];
  }
}

TEST(Characterize, TheDamperRecordHoldsTheResolvedModelChoices) {
  const std::string pipe = std::string(BAGDEM_SOURCE_DIR) + "/cases/pipe-beanbag";
  const bagdem::Scene scene = bagdem::load_case(pipe);
  const bagdem::study::DamperRecord made = bagdem::study::damper_record(scene);
  ASSERT_TRUE(made.count("model.film.bending_stiffness") && made.count("model.pair.ldpe/steel") && made.count("model.pair.steel/steel"));
  EXPECT_EQ(made.count("model.pair.aluminium/aluminium"), 1u) << "the cavity's material is the damper's";
  EXPECT_NE(made.at("model.pair.ldpe/steel").find("e 0.3"), std::string::npos) << made.at("model.pair.ldpe/steel");
  EXPECT_TRUE(bagdem::study::damper_differences(made, bagdem::study::damper_record(bagdem::load_case(pipe, {"simulation.seed=1"}))).empty())
      << "another seed fills the bag otherwise, the damper is the same";
  const std::vector<std::string> radius = {"bag.film.contact_radius=\"2 mm\""};
  EXPECT_TRUE(bagdem::study::damper_differences(bagdem::study::damper_record(bagdem::load_case(pipe, radius)),
                                                bagdem::study::damper_record(bagdem::load_case(pipe, {radius[0], "simulation.seed=1"})))
                  .empty())
      << "a radius the case gives in mm is the same for any seed";
  bagdem::Scene other = scene;
  auto bag = std::make_shared<bagdem::Bag>(*scene.bag);
  bag->film.bending_stiffness *= 2;
  other.bag = bag;
  std::vector<std::string> diff = bagdem::study::damper_differences(made, bagdem::study::damper_record(other));
  ASSERT_EQ(diff.size(), 1u);
  EXPECT_EQ(diff[0].rfind("model.film.bending_stiffness is 3.1", 0), 0u) << diff[0];
  bagdem::study::DamperRecord older;
  for (const auto& [k, v] : made)
    if (k.rfind("model.", 0) != 0) older[k] = v;
  diff = bagdem::study::damper_differences(older, made);
  ASSERT_EQ(diff.size(), 1u);
  EXPECT_NE(diff[0].find("made by an earlier bagdem"), std::string::npos) << diff[0];
  // The film's bending model (recorded when it is not the hinge, so the hinge's older maps stay the
  // case's) and the keys that set the time step are the damper's.
  EXPECT_EQ(made.count("model.film.bending_model"), 0u);
  EXPECT_EQ(made.count("simulation.timestep"), 0u) << "the automatic step is not recorded: the maps made before stay the case's";
  // A key given at its default is the same damper as the key left out, in a map that records the
  // defaults and in one recorded before they were; a default another bagdem changed is not.
  EXPECT_EQ(made.at("bag.film.shrink"), "(default) 1");
  bagdem::study::DamperRecord before_defaults;
  for (const auto& [k, v] : made)
    if (v.rfind("(default) ", 0) != 0) before_defaults[k] = v;
  EXPECT_TRUE(bagdem::study::damper_differences(before_defaults, made).empty()) << "left out in both";
  for (const std::string set : {"bag.film.shrink=1", "bag.film.bending_model=\"hinge\"", "bag.centre=[\"0 mm\", 0, \"-0 m\"]"}) {
    const bagdem::study::DamperRecord given = bagdem::study::damper_record(bagdem::load_case(pipe, {set}));
    EXPECT_TRUE(bagdem::study::damper_differences(made, given).empty()) << set << ": " << bagdem::study::damper_differences(made, given)[0];
    EXPECT_TRUE(bagdem::study::damper_differences(given, made).empty()) << set;
    // A map recorded before defaults were does not say what its bagdem's default was: refused.
    EXPECT_EQ(bagdem::study::damper_differences(before_defaults, given).size(), 1u) << set;
  }
  bagdem::study::DamperRecord changed_default = made;
  changed_default["bag.film.shrink"] = "(default) 0.9";
  diff = bagdem::study::damper_differences(changed_default, made);
  ASSERT_EQ(diff.size(), 1u);
  EXPECT_EQ(diff[0], "bag.film.shrink is 0.9 (the default) in the map, 1 (the default) in the case");
  diff = bagdem::study::damper_differences(made, bagdem::study::damper_record(bagdem::load_case(pipe, {"bag.film.shrink=0.95"})));
  ASSERT_EQ(diff.size(), 1u);
  EXPECT_EQ(diff[0], "bag.film.shrink is 1 (the default) in the map, 0.95 in the case");
  // A radius given "auto" is the default; the automatic step's factors are the damper's (a map
  // recorded before them is not asked for them).
  EXPECT_TRUE(bagdem::study::damper_differences(made, bagdem::study::damper_record(bagdem::load_case(pipe, {"bag.film.contact_radius=\"auto\""}))).empty());
  EXPECT_TRUE(made.count("model.film.contact_radius_per_edge"));
  bagdem::study::DamperRecord auto_before = bagdem::study::damper_record(bagdem::load_case(pipe, {"bag.film.contact_radius=\"auto\""}));
  auto_before.erase("model.film.contact_radius_per_edge");  // as recorded before the fraction was for a given "auto"
  EXPECT_TRUE(bagdem::study::damper_differences(auto_before, made).empty()) << bagdem::study::damper_differences(auto_before, made)[0];
  diff = bagdem::study::damper_differences(made, bagdem::study::damper_record(bagdem::load_case(pipe, {"simulation.timestep_safety=0.1"})));
  ASSERT_EQ(diff.size(), 1u);
  EXPECT_EQ(diff[0].rfind("simulation.timestep_safety is", 0), 0u) << diff[0];
  bagdem::study::DamperRecord before_factors = made;
  before_factors.erase("simulation.timestep_safety");
  EXPECT_TRUE(bagdem::study::damper_differences(before_factors, made).empty());
  for (const std::string& set : {std::string("bag.film.bending_model=\"quadratic\""), std::string("simulation.timestep=\"1e-6 s\"")}) {
    diff = bagdem::study::damper_differences(made, bagdem::study::damper_record(bagdem::load_case(pipe, {set})));
    ASSERT_FALSE(diff.empty()) << set;
    EXPECT_NE(diff[0].find(set.substr(set.find('.') + 1, set.find('=') - set.find('.') - 1)), std::string::npos) << diff[0];
  }
}
