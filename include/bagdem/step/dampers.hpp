// Several dampers on one structure (Scene::more_dampers, case key [[dampers]]): a Simulation per
// damper, each its own cavity, contents and film stepping in its own frame, stepped together. At
// each step every damper runs its stages up to the structure's (side by side on the threads, one
// damper to a thread, when they are large enough to be worth it); then the structure feels the load
// of them all, G_d m_d summed in the case's order of the dampers; then each runs the rest of the
// step. Each damper's simulation integrates the structure with that same load, so they all hold the
// same bits of it, and the results are the same bits for any number of threads. A scene of one
// damper is its Simulation alone, stepped as Simulation steps it (the same bits).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "bagdem/scene.hpp"
#include "bagdem/step/simulation.hpp"

namespace bagdem {

class Dampers {
 public:
  // scene: the case's own damper, with the others in scene.more_dampers (it outlives this).
  explicit Dampers(const Scene& scene);
  Dampers(const Dampers&) = delete;  // each simulation reads load_ where it is
  Dampers& operator=(const Dampers&) = delete;
  // The scene of damper k (0: the case's).
  const Scene& scene(std::size_t k) const { return sims_[k].scene(); }

  std::size_t size() const { return sims_.size(); }
  const std::string& name(std::size_t k) const { return names_[k]; }
  // Damper k's simulation (0: the case's own): its balls, film, cavity, energy budget; its
  // structure() is the structure, the same in each.
  const Simulation& operator[](std::size_t k) const { return sims_[k]; }
  Simulation& operator[](std::size_t k) { return sims_[k]; }

  void advance(std::uint64_t steps);
  // Tests: the dampers side by side on the threads whatever their size (the same bits either way).
  void set_parallel(bool on) { parallel_ = on && sims_.size() > 1; }
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
  // Every damper's state as one image (one damper: its Simulation's image), and its inverse.
  std::vector<char> image() const;
  void load_image(const std::vector<char>& image);

 private:
  // The load of all dampers now (each one's G m, summed in order) into load_; gather_load also
  // shares it with each.
  void sum_load();
  void gather_load();
  std::vector<Simulation> sims_;
  std::vector<std::string> names_;
  Eigen::VectorXd load_;
  // The dampers step side by side on the threads when each holds at least this many balls and film
  // nodes (a bag's step, tens of microseconds) and OMP_WAIT_POLICY is not passive; otherwise one
  // after another (the same bits).
  static constexpr std::size_t kParallelDamper = 64;
  bool parallel_ = false;
  std::vector<std::exception_ptr> errors_;  // advance's: each damper's failure in a step
};

}  // namespace bagdem
