// Layer 1 of 3 (neighbour search -> contact geometry -> contact law): a broad phase only returns
// candidate pairs. Every implementation returns the same set: all i < j with
// |x_i - x_j| < r_i + r_j + skin, grouped by i ascending and sorted by j within each i, so the
// result is canonical (independent of the method and of the thread count).
// Kinds (plain table in src/neighbour/broad_phase.cpp):
//   hash   : spatial hashing of integer cell coordinates, particles sorted by cell (default)
//   kdtree : nanoflann k-d tree radius search
//   brute  : O(N^2) reference, for tests
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bagdem/vec3.hpp"

namespace bagdem {

// Candidate pairs in CSR form: the partners of i are partner[begin[i] .. begin[i+1]), all > i.
struct CandidatePairs {
  std::vector<std::uint32_t> begin;    // size N + 1
  std::vector<std::uint32_t> partner;  // j of each pair
  std::size_t size() const { return partner.size(); }
};

class BroadPhase {
 public:
  virtual ~BroadPhase() = default;
  virtual void find(const std::vector<Vec3>& x, const std::vector<double>& r, double skin,
                    CandidatePairs& out) = 0;
};

struct BroadPhaseKind {
  const char* name;
  const char* summary;
  std::unique_ptr<BroadPhase> (*create)();
};

const std::vector<BroadPhaseKind>& broad_phase_kinds();
std::unique_ptr<BroadPhase> make_broad_phase(const std::string& name);  // throws on unknown

std::unique_ptr<BroadPhase> make_spatial_hash();
std::unique_ptr<BroadPhase> make_kdtree();
std::unique_ptr<BroadPhase> make_brute_force();

// Per-thread buffers of build_candidates, owned by each broad phase and reused between rebuilds.
struct CandidateScratch {
  std::vector<std::vector<std::uint32_t>> chunk;  // each thread's pairs, in i order
  std::vector<std::vector<std::uint32_t>> buf;    // each thread's partners of one i
};

// Shared by the implementations: turns per-i sorted partner lists, produced in parallel over
// contiguous blocks of i, into CSR. `collect(i, buffer)` appends the partners of i (any order).
template <class Collect>
void build_candidates(std::size_t n, CandidatePairs& out, CandidateScratch& scratch, Collect&& collect);

}  // namespace bagdem

#include "bagdem/neighbour/broad_phase_impl.hpp"
