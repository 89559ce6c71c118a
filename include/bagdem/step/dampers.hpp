// Several dampers on one structure (Scene::more_dampers, case key [[dampers]]): a Simulation per
// damper, each its own cavity, contents and film stepping in its own frame, stepped together. At
// each step every damper runs its stages up to the structure's (in parallel on the threads, one
// damper to a thread); then the structure feels the load of them all, G_d m_d summed in the case's
// order of the dampers; then each runs the rest of the step. Each damper's simulation integrates
// the structure with that same load, so they all hold the same bits of it, and the results are the
// same bits for any number of threads. One damper: use Simulation (the same bits as before).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "bagdem/scene.hpp"
#include "bagdem/step/simulation.hpp"

namespace bagdem {

class Dampers {
 public:
  // scene: the case's own damper, with the others in scene.more_dampers (it outlives this).
  explicit Dampers(const Scene& scene);

  std::size_t size() const { return sims_.size(); }
  const std::string& name(std::size_t k) const { return names_[k]; }
  // Damper k's simulation (0: the case's own): its balls, film, cavity, energy budget; its
  // structure() is the structure, the same in each.
  const Simulation& operator[](std::size_t k) const { return sims_[k]; }
  Simulation& operator[](std::size_t k) { return sims_[k]; }

  void advance(std::uint64_t steps);
  double time() const { return sims_[0].time(); }
  std::uint64_t steps_done() const { return sims_[0].steps_done(); }
  // The structure's response (its cavity and load columns: the case's own damper's).
  StructureResponse structure_response() const { return sims_[0].structure_response(); }
  // As Simulation's, for every damper.
  void set_drive_frequency(double hz);
  void jump_harmonic(const Eigen::VectorXcd& A, double w_a, const Eigen::VectorXcd& B, double w_b);
  // After each damper's simulation was restored (its load_state): the load of them all anew.
  void restored() { gather_load(); }
  std::vector<std::vector<char>> save_state() const;
  void load_state(const std::vector<std::vector<char>>& images);

 private:
  // The load of all dampers now (each one's G m, in order), shared with each.
  void gather_load();
  std::vector<Simulation> sims_;
  std::vector<std::string> names_;
  Eigen::VectorXd load_;
};

}  // namespace bagdem
