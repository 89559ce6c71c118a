// A sweep's checkpoint (sweep_state.hpp).
#include "sweep_state.hpp"

#include <cstring>
#include <string>
#include <type_traits>

#include "bagdem/error.hpp"
#include "checkpoint_file.hpp"

namespace bagdem {

namespace {

// The rows are stored as their bytes: every field, exactly.
static_assert(std::is_trivially_copyable_v<SweepPoint> && std::is_trivially_copyable_v<ReducedRow>,
              "a sweep's checkpoint stores points and reduced rows as bytes: give a field that is not "
              "trivially copyable its own block in sweep_state.cpp");
static_assert(std::is_trivially_copyable_v<SeriesLengths>);

template <class T>
std::string bytes(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <class T>
bool from_bytes(const std::string& b, std::vector<T>& v) {
  if (b.size() % sizeof(T) != 0) return false;
  v.resize(b.size() / sizeof(T));
  std::memcpy(static_cast<void*>(v.data()), b.data(), b.size());
  return true;
}

// settled, clearance and the lengths, as 8-byte fields.
struct Head {
  double settled = 0, clearance = 0;
  SeriesLengths lengths;
};
static_assert(sizeof(Head) == 2 * sizeof(double) + sizeof(SeriesLengths));

}  // namespace

void save_sweep_checkpoint(const std::filesystem::path& path, const Simulation& sim, const SweepState& s) {
  const Head h{s.settled ? 1.0 : 0.0, s.clearance, s.lengths};
  const std::vector<char> image = sim.save_state();
  save_checkpoint_file(path, {"sweep", sim.scene().resolved,
                              {std::string(reinterpret_cast<const char*>(&h), sizeof h), bytes(s.points), bytes(s.reduced),
                               bytes(s.frame_times), std::string(image.begin(), image.end())}});
}

std::vector<char> load_sweep_checkpoint(const std::filesystem::path& path, const Scene& scene, SweepState& s) {
  const CheckpointData d = load_checkpoint_file(path, "sweep");
  require_checkpoint_case(d, scene.case_file, scene.resolved);
  Head h;
  const bool ok = d.blocks.size() == 5 && d.blocks[0].size() == sizeof h && from_bytes(d.blocks[1], s.points) &&
                  from_bytes(d.blocks[2], s.reduced) && from_bytes(d.blocks[3], s.frame_times) &&
                  s.points.size() == s.reduced.size();
  if (!ok) throw InputError("checkpoint " + path.string() + " has not the blocks of a sweep; run again without --resume");
  std::memcpy(static_cast<void*>(&h), d.blocks[0].data(), sizeof h);
  s.settled = h.settled != 0;
  s.clearance = h.clearance;
  s.lengths = h.lengths;
  return std::vector<char>(d.blocks[4].begin(), d.blocks[4].end());
}

}  // namespace bagdem
