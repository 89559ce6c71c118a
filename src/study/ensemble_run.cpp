// `bagdem run CASE --seeds N`: the case as an ensemble of perturbed starts (study/study.hpp).
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "bagdem/io/table_csv.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

namespace {

// The number in a cell, NaN when empty or not a number.
double cell(const TextTable& t, const std::vector<std::string>& row, const std::string& name) {
  const std::size_t k = t.find(name);
  if (k == t.names.size() || row[k].empty()) return std::nan("");
  return std::strtod(row[k].c_str(), nullptr);
}

// Prints each mode's peak reduction over the starts, and warns when the starts did not differ.
void describe_ensemble(const fs::path& out, int seeds) {
  const fs::path peaks = out / "peaks_ensemble.csv", reduced = out / "reduced_ensemble.csv";
  if (fs::exists(peaks)) {
    const TextTable t = read_text_table(peaks);
    for (const auto& row : t.rows)
      std::printf("mode %g: reduction %.2f +- %.2f dB (95%% interval over %g starts), at the band's edge in %g of them\n",
                  cell(t, row, "mode_mean"), cell(t, row, "reduction_dB_mean"), cell(t, row, "reduction_dB_ci95"), cell(t, row, "n"),
                  std::round(cell(t, row, "at_band_edge_mean") * cell(t, row, "n")));
  }
  if (fs::exists(reduced)) {
    const TextTable t = read_text_table(reduced);
    for (const auto& row : t.rows)
      std::printf("%.5g Hz: M_eff/M_bag %.4g +- %.2g, C_b/(M_b w) %.4g +- %.2g, e %.3g +- %.2g (95%% intervals over %g starts)\n",
                  cell(t, row, "frequency_mean"), cell(t, row, "M_eff_ratio_mean"), cell(t, row, "M_eff_ratio_ci95"),
                  cell(t, row, "Cb_over_Mbw_mean"), cell(t, row, "Cb_over_Mbw_ci95"), cell(t, row, "e_mean"), cell(t, row, "e_ci95"),
                  cell(t, row, "n"));
    bool spread = false;
    for (const auto& row : t.rows) spread = spread || cell(t, row, "M_eff_sd") > 0 || cell(t, row, "C_eff_sd") > 0;
    if (!spread && !t.rows.empty())
      std::fprintf(stderr,
                   "warning: the %d starts gave the same results: simulation.seed changes nothing in this case (a bed read "
                   "from a file?), so the intervals do not cover the start-to-start spread\n",
                   seeds);
  }
  std::printf("ensemble tables: %s/<table>_ensemble.csv (mean, sd, se, ci95 over the starts)\n", out.string().c_str());
}

}  // namespace

int run_ensemble(const std::string& case_dir, const std::vector<std::string>& sets, int seeds, const std::string& out,
                 int threads) {
  SweepArgs a;
  a.dir = case_dir;
  a.sets = sets;
  a.seeds = seeds;
  a.threads = threads;
  a.command = "run --seeds";
  a.out = out.empty() ? (fs::path(case_dir) / "out").string() : out;
  const int code = sweep_command(a);
  if (code == 0) describe_ensemble(a.out, seeds);
  return code;
}

}  // namespace bagdem::study
