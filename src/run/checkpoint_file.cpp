// checkpoint.bin (checkpoint_file.hpp).
#include "checkpoint_file.hpp"

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/atomic_file.hpp"

namespace bagdem {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'b', 'a', 'g', 'd', 'e', 'm', 'C', 'K'};
constexpr std::uint64_t kMaxBytes = 1ULL << 40;  // a length beyond this is corruption, not data

void put_u64(std::string& s, std::uint64_t v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); }

void put_block(std::string& s, const std::string& b) {
  put_u64(s, b.size());
  s += b;
}

std::string hex(std::uint64_t v) {
  std::ostringstream s;
  s << "0x" << std::hex << v;
  return s.str();
}

// Reading the payload: a block past its end means the file was cut or its lengths changed.
struct Blocks {
  const std::string& in;
  std::size_t at = 0;
  bool take(std::string& out) {
    std::uint64_t n = 0;
    if (in.size() - at < sizeof n) return false;
    std::memcpy(&n, in.data() + at, sizeof n);
    at += sizeof n;
    if (n > in.size() - at) return false;
    out.assign(in, at, n);
    at += n;
    return true;
  }
};

}  // namespace

void save_checkpoint_file(const fs::path& path, const CheckpointData& data) {
  std::string payload;
  put_block(payload, data.kind);
  put_block(payload, data.case_text);
  put_block(payload, data.scene);
  put_u64(payload, data.blocks.size());
  for (const std::string& b : data.blocks) put_block(payload, b);
  std::string file(kMagic, sizeof kMagic);
  put_u64(file, kCheckpointFormat);
  put_u64(file, payload.size());
  put_u64(file, fnv1a64(payload.data(), payload.size()));
  file += payload;
  write_atomically(path, file);
}

CheckpointData load_checkpoint_file(const fs::path& path, const std::string& kind) {
  const std::string where = "checkpoint " + path.string();
  const std::string again = "; run again without --resume";
  std::ifstream f(path, std::ios::binary);
  if (!f)
    throw InputError(path.string(), "", "",
                     "no checkpoint to resume from (run without --resume; a run leaves one when interrupted or with "
                     "output.checkpoint_interval > 0)");
  const std::string file((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) throw InputError(where + " cannot be read" + again);
  constexpr std::size_t kHeader = sizeof kMagic + 3 * sizeof(std::uint64_t);
  std::uint64_t head[3] = {0, 0, 0};  // format, length, hash
  if (file.size() >= kHeader) std::memcpy(head, file.data() + sizeof kMagic, sizeof head);
  if (file.size() < kHeader || std::memcmp(file.data(), kMagic, sizeof kMagic) != 0 || head[0] != kCheckpointFormat)
    throw InputError(where + " is not a checkpoint of format " + std::to_string(kCheckpointFormat) +
                     " (written by another version of bagdem, or damaged)" + again);
  if (head[1] != file.size() - kHeader)
    throw InputError(where + " is corrupt: " + std::to_string(file.size() - kHeader) + " bytes of data where its header records " +
                     std::to_string(head[1]) + " (truncated?)" + again);
  const std::uint64_t sum = fnv1a64(file.data() + kHeader, file.size() - kHeader);
  if (sum != head[2])
    throw InputError(where + " is corrupt: checksum " + hex(sum) + " where its header records " + hex(head[2]) + again);
  const std::string payload = file.substr(kHeader);
  Blocks in{payload};
  CheckpointData d;
  std::string count;
  std::uint64_t n = 0;
  bool ok = in.take(d.kind) && in.take(d.case_text) && in.take(d.scene) && payload.size() - in.at >= sizeof n;
  if (ok) std::memcpy(&n, payload.data() + in.at, sizeof n), in.at += sizeof n;
  for (std::uint64_t k = 0; ok && k < n && n < kMaxBytes; ++k) ok = in.take(d.blocks.emplace_back());
  if (!ok || in.at != payload.size()) throw InputError(where + " is corrupt: its blocks do not fill it" + again);
  if (d.kind != kind)
    throw InputError(where + " is a checkpoint of a " + d.kind + ", not of a " + kind + again);
  return d;
}

namespace {
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}
}  // namespace

CheckpointData checkpoint_of(const std::string& kind, const Scene& scene, std::vector<std::string> blocks) {
  std::string record;
  for (const std::string& line : scene_record(scene)) record += line + "\n";
  return {kind, scene.resolved, record, std::move(blocks)};
}

void require_checkpoint_case(const CheckpointData& data, const Scene& scene) {
  if (data.case_text != scene.resolved)
    throw InputError(scene.case_file, "", "",
                     "the case differs from the one of the interrupted run (" + case_differences(data.case_text, scene.resolved) +
                         "); resume with the same case and --set options, or run again without --resume");
  const std::string diff = scene_difference(lines_of(data.scene), scene_record(scene));
  if (!diff.empty())
    throw InputError(scene.case_file, "", "",
                     "this bagdem resolves the case to another scene than the interrupted run's (another default or rule: " + diff +
                         "); resume with the bagdem that ran it, or run again without --resume");
}

}  // namespace bagdem
