// The points of a stepped sine shared among its chains (stepped_sine_chains.hpp).
#include "stepped_sine_chains.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bagdem {

std::size_t chain_count(std::size_t chains, std::size_t planned) {
  return std::max<std::size_t>(1, std::min(chains, planned));
}

std::vector<ChainTask> planned_tasks(const std::vector<double>& frequencies, std::size_t chains) {
  const std::size_t n = frequencies.size(), K = chain_count(chains, n);
  std::vector<ChainTask> tasks;
  std::size_t first = 0;
  for (std::size_t k = 0; k < K; ++k) {
    const std::size_t len = n / K + (k < n % K ? 1 : 0);
    for (std::size_t i = first; i < first + len; ++i)
      tasks.push_back({i, frequencies[i], k, i == first ? ChainTask::none : tasks.back().index});
    first += len;
  }
  return tasks;
}

std::size_t refinement_rounds(std::size_t refine, std::size_t chains) {
  const std::size_t K = std::max<std::size_t>(1, chains);
  return (refine + K - 1) / K;
}

std::size_t round_points(std::size_t refine, std::size_t chains, std::size_t round) {
  const std::size_t K = std::max<std::size_t>(1, chains), placed = round * K;
  return placed < refine ? std::min(K, refine - placed) : 0;
}

// The contents' dynamic stiffness at the cavity, Z = -L / U (their force's and the cavity's first
// harmonics) measured at a point, as a mass and a dashpot (Z = -w^2 M_e + i w C_e) at w: how a stepped sine
// point's start predicts the contents (Primary::steady_amplitudes). NaN without a cavity motion.
std::complex<double> contents_stiffness(const SteppedSinePoint& p, double w) {
  const double w0 = 2 * std::numbers::pi * p.frequency;
  if (!(std::abs(p.cavity) > 0)) return {std::nan(""), std::nan("")};
  const std::complex<double> Z0 = -p.contents_force / p.cavity;
  return {Z0.real() * (w * w) / (w0 * w0), Z0.imag() * w / w0};
}

std::vector<ChainTask> refinement_tasks(const Primary& P, const std::vector<SteppedSinePoint>& done, std::size_t per_mode,
                                        std::size_t chains, double dt, std::size_t first_index) {
  std::vector<ChainTask> tasks;
  const std::size_t K = std::max<std::size_t>(1, chains);
  for (const ModePoints& m : group_by_mode(P, done))
    for (double f : refinement_frequencies(m, dt, per_mode)) {
      const std::size_t j = tasks.size();
      std::size_t near = 0;
      for (std::size_t i = 1; i < done.size(); ++i)
        if (std::abs(std::log(done[i].frequency / f)) < std::abs(std::log(done[near].frequency / f))) near = i;
      tasks.push_back({first_index + j, f, j % K, done.empty() ? ChainTask::none : near});
    }
  return tasks;
}

}  // namespace bagdem
