// A stepped sine's checkpoint (stepped_sine_state.hpp).
#include "stepped_sine_state.hpp"

#include <cstring>
#include <sstream>
#include <string>
#include <type_traits>

#include "bagdem/error.hpp"
#include "checkpoint_file.hpp"
#include "bagdem/interrupt.hpp"
#include "output_files.hpp"

namespace bagdem {

namespace {

// The points are stored as their bytes: every field, exactly.
static_assert(std::is_trivially_copyable_v<SteppedSinePoint>,
              "a sweep's checkpoint stores its points as bytes: give a field that is not trivially copyable "
              "its own block in stepped_sine_state.cpp");
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

// Reduced rows as the numbers of reduced_values (every field, reduce.cpp) and their e_method
// texts, one per line.
std::string reduced_numbers(const std::vector<ReducedRow>& rows) {
  std::vector<double> v;
  for (const ReducedRow& r : rows) {
    const std::vector<double> x = reduced_values(r);
    v.insert(v.end(), x.begin(), x.end());
  }
  return bytes(v);
}

std::string reduced_methods(const std::vector<ReducedRow>& rows) {
  std::string t;
  for (const ReducedRow& r : rows) t += r.e_method + "\n";
  return t;
}

bool reduced_from(const std::string& numbers, const std::string& methods, std::vector<ReducedRow>& rows) {
  std::vector<double> v;
  const std::size_t n = reduced_values(ReducedRow{}).size();
  if (!from_bytes(numbers, v) || v.size() % n != 0) return false;
  std::size_t at = 0;
  for (std::size_t k = 0; k < v.size(); k += n) {
    const std::size_t end = methods.find('\n', at);
    if (end == std::string::npos) return false;
    rows.push_back(reduced_row(std::vector<double>(v.begin() + k, v.begin() + k + n), methods.substr(at, end - at)));
    at = end + 1;
  }
  return at == methods.size();
}

// settled, clearance and the lengths, as 8-byte fields.
struct Head {
  double settled = 0, clearance = 0;
  SeriesLengths lengths;
};
static_assert(sizeof(Head) == 2 * sizeof(double) + sizeof(SeriesLengths));

// Several dampers: a block that starts with this, then per damper but the case's own its clearance,
// its reduced rows' numbers and their methods, each as a length and its bytes.
constexpr char kMoreDampers[] = "bagdem more dampers\n";

std::string more_dampers_block(const SteppedSineState& s) {
  std::string b = kMoreDampers;
  auto part = [&](const std::string& x) {
    const std::uint64_t n = x.size();
    b.append(reinterpret_cast<const char*>(&n), sizeof n), b += x;
  };
  for (std::size_t k = 0; k < s.more_clearance.size(); ++k)
    part(bytes(std::vector<double>{s.more_clearance[k]})), part(reduced_numbers(s.more_reduced[k])), part(reduced_methods(s.more_reduced[k]));
  return b;
}

bool more_dampers_from(const std::string& b, SteppedSineState& s) {
  std::size_t at = sizeof kMoreDampers - 1;
  auto part = [&](std::string& x) {
    std::uint64_t n = 0;
    if (at + sizeof n > b.size()) return false;
    std::memcpy(&n, b.data() + at, sizeof n);
    at += sizeof n;
    if (at + n > b.size()) return false;
    x = b.substr(at, n), at += n;
    return true;
  };
  while (at < b.size()) {
    std::string c, numbers, methods;
    std::vector<double> clearance;
    auto& rows = s.more_reduced.emplace_back();
    if (!part(c) || !part(numbers) || !part(methods) || !from_bytes(c, clearance) || clearance.size() != 1 || !reduced_from(numbers, methods, rows) ||
        rows.size() != s.points.size())
      return false;
    s.more_clearance.push_back(clearance[0]);
  }
  return true;
}

}  // namespace

// Blocks: the head, the points, the reduced rows (numbers, methods), the frame times, with several
// dampers the others' block (more_dampers_block), then one image per chain.
void save_stepped_sine_checkpoint(const std::filesystem::path& path, const Scene& scene, const SteppedSineState& s) {
  const Head h{s.settled ? 1.0 : 0.0, s.clearance, s.lengths};
  CheckpointData d = checkpoint_of("sweep", scene,
                                   {std::string(reinterpret_cast<const char*>(&h), sizeof h), bytes(s.points), reduced_numbers(s.reduced),
                                    reduced_methods(s.reduced), bytes(s.frame_times)});
  if (!s.more_clearance.empty()) d.blocks.push_back(more_dampers_block(s));
  for (const std::vector<char>& image : s.images) d.blocks.emplace_back(image.begin(), image.end());
  save_checkpoint_file(path, d);
}

void load_stepped_sine_checkpoint(const std::filesystem::path& path, const Scene& scene, SteppedSineState& s) {
  const CheckpointData d = load_checkpoint_file(path, "sweep");
  require_checkpoint_case(d, scene);
  Head h;
  const bool ok = d.blocks.size() >= 6 && d.blocks[0].size() == sizeof h && from_bytes(d.blocks[1], s.points) &&
                  reduced_from(d.blocks[2], d.blocks[3], s.reduced) && from_bytes(d.blocks[4], s.frame_times) &&
                  s.points.size() == s.reduced.size();
  if (!ok) throw InputError("checkpoint " + path.string() + " has not the blocks of a sweep; run again without --resume");
  std::memcpy(static_cast<void*>(&h), d.blocks[0].data(), sizeof h);
  s.settled = h.settled != 0;
  s.clearance = h.clearance;
  s.lengths = h.lengths;
  s.images.clear(), s.more_clearance.clear(), s.more_reduced.clear();
  std::size_t b = 5;
  if (d.blocks[5].rfind(kMoreDampers, 0) == 0) {
    if (!more_dampers_from(d.blocks[5], s) || d.blocks.size() < 7)
      throw InputError("checkpoint " + path.string() + " has not the blocks of a sweep; run again without --resume");
    b = 6;
  }
  for (; b < d.blocks.size(); ++b) s.images.emplace_back(d.blocks[b].begin(), d.blocks[b].end());
}

std::string interrupted_message(int signal, double t, std::size_t points, const std::filesystem::path& out) {
  std::ostringstream m;
  m << signal_name(signal) << " at t = " << t << " s after " << points << " points: " << (out / "results.h5.part").string()
    << " and " << (out / "checkpoint.bin").string() << " kept; continue with --resume (a point cut short is run again)";
  return m.str();
}

void start_stepped_sine_state(const std::filesystem::path& out, bool resume, Dampers& sim, SteppedSineState& state) {
  const std::filesystem::path ckpt = out / "checkpoint.bin", part = out / "results.h5.part";
  if (resume) {
    load_stepped_sine_checkpoint(ckpt, sim.scene(0), state);
    if (state.more_clearance.size() + 1 != sim.size())
      throw InputError(ckpt.string(), "", "", "the checkpoint holds " + std::to_string(state.more_clearance.size() + 1) + " damper(s), the case " +
                                                  std::to_string(sim.size()) + "; run again without --resume");
    if (!std::filesystem::exists(part))
      throw InputError(part.string(), "", "", "the partial results file of the interrupted sweep is missing; run again without --resume");
    try {
      sim.load_image(state.images.front());
    } catch (const std::exception& e) {
      throw InputError(ckpt.string(), "", "", std::string(e.what()) + "; run again without --resume");
    }
  } else {
    std::filesystem::remove(ckpt);
  }
  // The tables of an earlier run go; its results.h5 stays until this stepped sine's replaces it.
  remove_derived_tables(out);
}

}  // namespace bagdem
