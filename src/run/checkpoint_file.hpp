// Internal to src/run: checkpoint.bin, what a run or a sweep needs to continue after an
// interruption (--resume), in a file that is verified before it is used.
//
// Layout (little-endian): the magic "bagdemCK", the format number (u64), the payload's length in
// bytes (u64) and its FNV-1a 64-bit hash (u64), then the payload: the kind ("run" or "sweep"), the
// resolved case text, the scene's record (scene_record) and the kind's own blocks, each block a u64 length and its bytes. Any byte
// changed in the payload changes the hash; a changed header fails the magic, format or length.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "bagdem/fingerprint.hpp"  // fnv1a64
#include "bagdem/scene.hpp"

namespace bagdem {

// 1: no header, no checksum; 2: no digest of the results file's data (SeriesLengths::digest);
// 3: no scene record
inline constexpr std::uint64_t kCheckpointFormat = 4;

struct CheckpointData {
  std::string kind;                 // "run" or "sweep"
  std::string case_text;            // the resolved case (a resume with another case is refused)
  std::string scene;                // scene_record's lines, each ended by a newline (a bagdem that
                                    // resolves the case otherwise is refused)
  std::vector<std::string> blocks;  // the kind's own data
};

// A checkpoint of `kind` of `scene` holding `blocks`.
CheckpointData checkpoint_of(const std::string& kind, const Scene& scene, std::vector<std::string> blocks);

// Writes the checkpoint atomically (a temporary name, then rename); throws std::runtime_error
// naming the file when it cannot be written (a full disk).
void save_checkpoint_file(const std::filesystem::path& path, const CheckpointData& data);

// Reads and verifies a checkpoint of `kind`: InputError (exit 2) naming the file when it is
// missing, of another format or kind, truncated, or its checksum does not match.
CheckpointData load_checkpoint_file(const std::filesystem::path& path, const std::string& kind);

// Refuses (InputError) a resume whose case, or the scene this bagdem resolves it to, differs from
// the checkpoint's, naming the first difference.
void require_checkpoint_case(const CheckpointData& data, const Scene& scene);

}  // namespace bagdem
