// summary.json is one type (reduce/summary.hpp), written and read by the same code: every field
// comes back as written (NaN as null and back), and a damaged or foreign file is refused naming
// the file and the key, never read as figures.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "bagdem/error.hpp"
#include "bagdem/reduce/summary.hpp"
#include "support.hpp"

namespace {

using bagdem::Summary;
using bagdem::SummaryKind;
using bagdem::testing::TempDir;

Summary a_run() {
  Summary s;
  s.case_file = "cases/pipe \"beanbag\"/case.toml", s.particles = 812, s.steps = 123456789012ULL, s.dt = 2.3456789012345e-7;
  s.dt_reason = "Hertz contact time / 50\nof the stiffest pair", s.threads = 2, s.wall_time = 12.5;
  s.particle_steps_per_second = 3.25e7, s.ns_per_particle_step = 30.7, s.neighbour_builds = 77;
  s.energy = bagdem::EnergySample{1, 2, 3, 4, 5, 6, 7, 8};
  s.energy_balance_error = 1.25e-9;
  s.bag = bagdem::SummaryBag{812, 760, 0.57, bagdem::Vec3(0.1, 0.02, 0.03), 5631, 5, 17};
  bagdem::SummaryStructure st;
  st.kind = "beam", st.response_at = 0.7, st.response_rms = 1e-4, st.acceleration_rms = 3.5;
  st.band = bagdem::SummaryBand{2e-5, 50, 400, 0.2};
  st.work_external = 1.5, st.work_contents = -0.5, st.dissipated = 0.25, st.energy = 0.125;
  st.decay = bagdem::DecayFit{.rate = 3, .damped_frequency = 41.5, .zeta = 0.01, .decay_time = 0.7, .measured_decay_time = NAN, .peaks = 12};
  s.structure = st;
  s.cycles_measured = 20;  // dissipated_per_cycle stays NaN: written null, read NaN
  return s;
}

Summary a_stepped_sine() {
  Summary s;
  s.kind = SummaryKind::stepped_sine;
  s.case_file = "c", s.particles = 3, s.dt = 1e-6, s.threads = 1, s.wall_time = 2, s.chains = 2, s.points = 6, s.not_steady = 1;
  s.force_amplitude = 0.2;
  s.peaks_missing = {"no peak reduction for mode 2: every one of its 2 points was unsteady"};
  bagdem::ModePeak m;
  m.name = "mode 1", m.mode = 1, m.bare_frequency = 30, m.bare_peak = 1e-3, m.frequency = 29.5, m.peak = 2e-4;
  m.simulated_frequency = 29.4, m.simulated_peak = 2.1e-4, m.peak_ci95 = NAN, m.reduction_db = 14.2, m.reduction_db_ci95 = 0.8;
  m.reduction_percent = 80.5, m.at_band_edge = true, m.unsteady_points = 1;
  s.peaks = {m};
  return s;
}

// Equal, NaN equal to NaN.
void same(double a, double b, const char* what) {
  if (std::isnan(a)) EXPECT_TRUE(std::isnan(b)) << what;
  else EXPECT_EQ(a, b) << what;
}

TEST(Summary, ARunComesBackAsWritten) {
  TempDir d;
  const Summary a = a_run();
  bagdem::write_summary(d.path / "summary.json", a);
  const Summary b = bagdem::read_summary(d.path / "summary.json");
  EXPECT_EQ(b.kind, SummaryKind::run);
  EXPECT_EQ(b.case_file, a.case_file);
  EXPECT_EQ(b.dt_reason, a.dt_reason);
  EXPECT_EQ(b.particles, a.particles);
  EXPECT_EQ(b.steps, a.steps);
  EXPECT_EQ(b.neighbour_builds, a.neighbour_builds);
  EXPECT_EQ(b.threads, a.threads);
  same(b.dt, a.dt, "dt (every digit)");
  same(b.energy_balance_error, a.energy_balance_error, "energy_balance_error");
  same(b.dissipated_per_cycle, a.dissipated_per_cycle, "dissipated_per_cycle (null)");
  ASSERT_TRUE(b.energy && b.bag && b.structure && b.structure->band && b.structure->decay);
  EXPECT_EQ(b.energy->terms(), a.energy->terms());
  EXPECT_EQ(b.bag->film_triangles, 760u);
  EXPECT_EQ(b.bag->outer, a.bag->outer);
  EXPECT_EQ(b.bag->self_steps, 5631u);
  EXPECT_EQ(b.bag->self_pairs_max, 5u);
  EXPECT_EQ(b.bag->wall_stops, 17u);
  EXPECT_EQ(b.structure->kind, "beam");
  same(b.structure->band->response_rms, 2e-5, "band_response_rms_m");
  same(b.structure->band->hi, 400, "band_Hz");
  same(b.structure->decay->measured_decay_time, NAN, "measured_decay_time_20dB_s");
  EXPECT_EQ(b.structure->decay->peaks, 12u);
}

TEST(Summary, AStepSineComesBackAsWritten) {
  TempDir d;
  const Summary a = a_stepped_sine();
  bagdem::write_summary(d.path / "summary.json", a);
  const Summary b = bagdem::read_summary(d.path / "summary.json");
  EXPECT_EQ(b.kind, SummaryKind::stepped_sine);
  EXPECT_EQ(b.chains, 2u);
  EXPECT_EQ(b.not_steady, 1u);
  EXPECT_EQ(b.peaks_missing, a.peaks_missing);
  ASSERT_EQ(b.peaks.size(), 1u);
  EXPECT_EQ(b.peaks[0].name, "mode 1");
  EXPECT_EQ(b.peaks[0].mode, 1u);
  EXPECT_TRUE(b.peaks[0].at_band_edge);
  same(b.peaks[0].peak_ci95, NAN, "peak_ci95 (null)");
  same(b.peaks[0].reduction_db, 14.2, "reduction_dB");
}

// A refusal names the file and the key.
void expect_refused(const std::string& text, const std::string& key) {
  TempDir d;
  std::ofstream(d.path / "summary.json") << text;
  try {
    (void)bagdem::read_summary(d.path / "summary.json");
    ADD_FAILURE() << "read without a word:\n" << text;
  } catch (const bagdem::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("summary.json"), std::string::npos) << what;
    EXPECT_NE(what.find(key), std::string::npos) << "the refusal does not name '" << key << "': " << what;
  }
}

TEST(Summary, ADamagedFileIsRefusedNamingTheKey) {
  TempDir d;
  bagdem::write_summary(d.path / "summary.json", a_run());
  std::string good;
  {
    std::ifstream in(d.path / "summary.json");
    good.assign(std::istreambuf_iterator<char>(in), {});
  }
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const std::size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? t : t.replace(at, from.size(), to);
  };
  expect_refused(good.substr(0, good.size() / 2), "not a JSON document");          // cut short (a crash mid-write)
  expect_refused(replaced("\"status\": \"complete\"", "\"status\": \"running\""), "status");
  expect_refused(replaced("\"particles\": 812", "\"particles\": \"812\""), "particles");
  expect_refused(replaced("\"particles\": 812", "\"particles\": -3"), "particles");
  expect_refused(replaced("\"steps\": 123456789012,", ""), "steps");
  expect_refused(replaced("\"kind\": \"run\"", "\"kind\": \"movie\""), "kind");
  expect_refused(replaced("\"packing_fraction\": 0.57", "\"packing_fraction\": true"), "packing_fraction");
  expect_refused(replaced("\"film_self_steps\": 5631", "\"film_self_steps\": -2"), "film_self_steps");
  expect_refused(replaced("\"film_self_pairs_max\": 5", "\"film_self_pairs_max\": \"5\""), "film_self_pairs_max");
  expect_refused(replaced("\"film_wall_stops\": 17", "\"film_wall_stops\": 1.5"), "film_wall_stops");
  expect_refused(replaced("\"band_Hz\": [", "\"band_Hz\": [1, "), "band_Hz");
}

}  // namespace
