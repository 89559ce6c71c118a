// Several dampers on one structure (step/dampers.hpp).
#include "bagdem/step/dampers.hpp"

#include <omp.h>

#include <algorithm>
#include <exception>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <strings.h>
#include <stdexcept>

#include "bagdem/error.hpp"
#include "stepper.hpp"

namespace bagdem {

Dampers::Dampers(const Scene& scene) {
  if (!scene.primary && !scene.more_dampers.empty()) throw std::logic_error("Dampers: several dampers need a primary structure");
  sims_.push_back(Simulation(scene, Simulation::OneOfSeveral{}));
  names_.push_back(scene.damper_name);
  for (const Damper& d : scene.more_dampers) {
    sims_.push_back(Simulation(*d.scene, Simulation::OneOfSeveral{}));
    names_.push_back(d.name);
  }
  if (sims_.size() == 1) return;
  // Side by side on the threads only when each damper's step is worth a fork and a join, and the
  // threads spin between steps: with OMP_WAIT_POLICY=passive each fork wakes sleeping threads, which
  // costs more than a bag's step (docs/performance.md, "Several dampers").
  std::size_t least = SIZE_MAX;
  for (const Simulation& s : sims_) least = std::min(least, s.particles().size() + s.film().size());
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  parallel_ = least >= kParallelDamper && !(policy && strcasecmp(policy, "passive") == 0);
  gather_load();
  for (Simulation& s : sims_) s.s_->restart_structure();  // a released structure's acceleration with every damper's load
}

void Dampers::sum_load() {
  load_ = sims_[0].s_->contents_load();
  for (std::size_t k = 1; k < sims_.size(); ++k) load_ += sims_[k].s_->contents_load();
}

void Dampers::gather_load() {
  if (sims_.size() == 1) return;
  sum_load();
  for (Simulation& s : sims_) s.s_->share_load(&load_);
}

void Dampers::advance(std::uint64_t steps) {
  if (sims_.size() == 1) return sims_[0].advance(steps);
  const int n = static_cast<int>(sims_.size());
  const int threads = parallel_ ? std::min(n, omp_get_max_threads()) : 1;
  // A damper's failure (a guard's RunError) cannot leave the parallel region: each damper's is kept
  // and the first, in the dampers' order, is thrown after it, naming the damper.
  std::vector<std::exception_ptr>& errors = errors_;  // sized once (a sweep advances one step at a time)
  errors.assign(sims_.size(), nullptr);
  auto each = [&](int team, auto&& part) {
#pragma omp parallel for schedule(static, 1) num_threads(team)
    for (int d = 0; d < n; ++d) {
      try {
        part(*sims_[static_cast<std::size_t>(d)].s_);
      } catch (...) {
        errors[static_cast<std::size_t>(d)] = std::current_exception();
      }
    }
    for (std::size_t d = 0; d < errors.size(); ++d) {
      if (!errors[d]) continue;
      try {
        std::rethrow_exception(errors[d]);
      } catch (const RunError& e) {
        throw RunError("damper " + names_[d] + ": " + e.what());
      }
    }
  };
  for (std::uint64_t k = 0; k < steps; ++k) {
    const bool last = k + 1 == steps;
    each(threads, [last](Stepper& s) { s.step_contents(last); });
    sum_load();
    each(threads, [](Stepper& s) { s.step_structure(); });
  }
}

void Dampers::set_drive_frequency(double hz) {
  for (Simulation& s : sims_) s.set_drive_frequency(hz);
}

void Dampers::jump_harmonic(const Eigen::VectorXcd& A, double w_a, const Eigen::VectorXcd& B, double w_b) {
  for (Simulation& s : sims_) s.jump_harmonic(A, w_a, B, w_b);
}

std::vector<std::vector<char>> Dampers::save_state() const {
  std::vector<std::vector<char>> images;
  for (const Simulation& s : sims_) images.push_back(s.save_state());
  return images;
}

void Dampers::load_state(const std::vector<std::vector<char>>& images) {
  if (images.size() != sims_.size()) throw std::runtime_error("a checkpoint of " + std::to_string(images.size()) + " dampers for " + std::to_string(sims_.size()));
  for (std::size_t k = 0; k < sims_.size(); ++k) sims_[k].load_state(images[k]);
  gather_load();
}

// Several: the count, each image's length, then the images.
std::vector<char> Dampers::image() const {
  if (sims_.size() == 1) return sims_[0].save_state();
  std::vector<std::vector<char>> images = save_state();
  std::vector<std::uint64_t> head{images.size()};
  for (const auto& i : images) head.push_back(i.size());
  std::vector<char> out(reinterpret_cast<const char*>(head.data()), reinterpret_cast<const char*>(head.data() + head.size()));
  for (const auto& i : images) out.insert(out.end(), i.begin(), i.end());
  return out;
}

void Dampers::load_image(const std::vector<char>& image) {
  if (sims_.size() == 1) return sims_[0].load_state(image);
  const auto word = [&](std::size_t k) {
    std::uint64_t v = 0;
    if ((k + 1) * sizeof v > image.size()) throw std::runtime_error("a state image of several dampers is cut short");
    std::memcpy(&v, image.data() + k * sizeof v, sizeof v);
    return v;
  };
  const std::uint64_t n = word(0);
  if (n != sims_.size()) throw std::runtime_error("a state image of " + std::to_string(n) + " dampers for " + std::to_string(sims_.size()));
  std::vector<std::vector<char>> images;
  std::size_t at = (n + 1) * sizeof(std::uint64_t);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint64_t len = word(k + 1);
    if (at + len > image.size()) throw std::runtime_error("a state image of several dampers is cut short");
    images.emplace_back(image.begin() + static_cast<std::ptrdiff_t>(at), image.begin() + static_cast<std::ptrdiff_t>(at + len));
    at += len;
  }
  load_state(images);
}

}  // namespace bagdem
