// Simulation: the public face of the stepper (stepper.hpp), one call through to it each.
#include "bagdem/step/simulation.hpp"

#include "bagdem/error.hpp"
#include "stepper.hpp"

namespace bagdem {

Simulation::Simulation(const Scene& scene) {
  if (!scene.more_dampers.empty())
    throw InputError(scene.case_file, "dampers", "", "the case holds " + std::to_string(1 + scene.more_dampers.size()) +
                                                         " dampers ([[dampers]]); this command runs one damper (several run with `bagdem run`, and `bagdem sweep` "
                                                         "of such runs): run each damper as its own case");
  s_ = std::make_unique<Stepper>(scene);
}
Simulation::Simulation(const Scene& scene, OneOfSeveral) : s_(std::make_unique<Stepper>(scene)) {}
Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

void Simulation::advance(std::uint64_t steps) { s_->advance(steps); }
const Scene& Simulation::scene() const { return s_->scene(); }
double Simulation::time() const { return s_->time(); }
std::uint64_t Simulation::steps_done() const { return s_->steps_done(); }

const Particles& Simulation::particles() const { return s_->particles(); }
Particles& Simulation::particles() { return s_->particles(); }
const std::vector<std::uint32_t>& Simulation::input_index() const { return s_->input_index(); }
const FilmNodes& Simulation::film() const { return s_->film(); }
FilmSelfContact Simulation::film_self_contact() const { return s_->film_self_contact(); }
std::uint64_t Simulation::film_wall_stops() const { return s_->film_wall_stops(); }
Vec3 Simulation::contents_relative_velocity() const { return s_->contents_relative_velocity(); }
void Simulation::add_contents_velocity(const Vec3& dv) { s_->add_contents_velocity(dv); }
std::vector<std::size_t> Simulation::balls_outside_bag() const { return s_->balls_outside_bag(); }

std::size_t Simulation::contact_count() const { return s_->contact_count(); }
std::size_t Simulation::mesh_contact_count() const { return s_->mesh_contact_count(); }
std::uint64_t Simulation::neighbour_builds() const { return s_->neighbour_builds(); }
PairListSize Simulation::pair_list() const {
  const PairState& ps = s_->pair_state();
  PairListSize size{ps.pairs.size(), 0, ps.cross.size()};
  for (const std::uint8_t t : ps.touching) size.touching += t;
  return size;
}
std::vector<std::pair<std::uint32_t, std::uint32_t>> Simulation::cross_pairs() const {
  const PairState& ps = s_->pair_state();
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (const std::uint32_t k : ps.cross) out.emplace_back(ps.first[k], ps.pairs.partner[k]);
  return out;
}

const CavityState& Simulation::cavity() const { return s_->cavity(); }
CavitySample Simulation::take_cavity_sample() { return s_->take_cavity_sample(); }
const StructureState& Simulation::structure() const { return s_->structure(); }
StructureResponse Simulation::structure_response() const { return s_->structure_response(); }
double Simulation::structure_energy() const { return s_->structure_energy(); }
void Simulation::set_drive_frequency(double hz) { s_->set_drive_frequency(hz); }
void Simulation::jump_harmonic(const Eigen::VectorXcd& A, double w_a, const Eigen::VectorXcd& B, double w_b) {
  s_->jump_harmonic(A, w_a, B, w_b);
}

double Simulation::initial_stored_energy() const { return s_->initial_stored_energy(); }
EnergySample Simulation::energy() const { return s_->energy(); }

std::vector<char> Simulation::save_state() const { return s_->save_state(); }
void Simulation::load_state(const std::vector<char>& image) { s_->load_state(image); }

void Simulation::set_profiling(bool on) { s_->set_profiling(on); }
const StageTimes& Simulation::stage_times() const { return s_->stage_times(); }
void Simulation::set_fusion(bool on) { s_->set_fusion(on); }
std::uint64_t Simulation::fused_steps() const { return s_->fused_steps(); }
void Simulation::set_pipelining(bool on) { s_->set_pipelining(on); }
std::uint64_t Simulation::pipelined_steps() const { return s_->pipelined_steps(); }
void Simulation::set_parallel_balls(std::size_t n) { s_->set_parallel_balls(n); }
void Simulation::set_balance_window(std::uint32_t steps, double tolerance) { s_->set_balance_window(steps, tolerance); }
void Simulation::set_cuts(std::vector<std::uint32_t> cuts) { s_->set_cuts(std::move(cuts)); }
const SpanBalance& Simulation::balance() const { return s_->balance(); }

}  // namespace bagdem
