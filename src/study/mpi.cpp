// The ranks of an MPI launch (study/study.hpp, Ranks). MPI is initialised only here, by the sweep
// command, and only when a launcher started the process: a plain `bagdem sweep` of an MPI build
// never starts MPI's runtime. The ranks on one node (MPI_Comm_split_type, MPI_COMM_TYPE_SHARED:
// what Open MPI also gives as OMPI_COMM_WORLD_LOCAL_SIZE) share its cores: each takes its own
// affinity mask when the launcher bound them to disjoint cores, else an equal part of their cores.
#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "bagdem/error.hpp"
#include "bagdem/study/study.hpp"

#ifdef BAGDEM_WITH_MPI
// The C API only: MPI's deprecated C++ bindings do not compile cleanly under -Wextra.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace bagdem::study {

bool launched_by_mpi() {
  // Open MPI's mpirun, PMIx launchers (srun --mpi=pmix, prterun), MPICH's hydra and PMI-1/2 srun.
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

#ifdef BAGDEM_WITH_MPI

Ranks::Ranks() {
  cores_ = machine_cores();
  cores_from_ = "the " + std::to_string(cores_) + " cores of this machine";
  if (!launched_by_mpi()) return;
  MPI_Init(nullptr, nullptr);
  initialised_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &local_size_);
  if (local_size_ > 1) {
    // The node's ranks compare their affinity masks. mpirun binds each rank to its own cores by
    // default (then a rank's mask is its share); unbound ranks all see the whole node (then they
    // divide it). Masks that overlap without being equal are divided too: never more than a share.
    cpu_set_t mine;
    CPU_ZERO(&mine);
    sched_getaffinity(0, sizeof mine, &mine);
    std::vector<cpu_set_t> all(static_cast<std::size_t>(local_size_));
    MPI_Allgather(&mine, sizeof mine, MPI_BYTE, all.data(), sizeof mine, MPI_BYTE, node);
    cpu_set_t joint, overlap;
    CPU_ZERO(&joint);
    bool disjoint = true;
    for (const cpu_set_t& m : all) {
      CPU_AND(&overlap, &joint, &m);
      disjoint = disjoint && CPU_COUNT(&overlap) == 0;
      CPU_OR(&joint, &joint, &m);
    }
    if (disjoint) {
      cores_from_ = "the " + std::to_string(cores_) + " cores this rank is bound to";
    } else {
      const int node_cores = CPU_COUNT(&joint);
      cores_ = std::max(1, node_cores / local_size_);
      cores_from_ = std::to_string(node_cores) + " cores on this node shared by its " + std::to_string(local_size_) + " ranks";
    }
  }
  MPI_Comm_free(&node);
}

Ranks::~Ranks() {
  if (initialised_) MPI_Finalize();
}

void Ranks::barrier() const {
  if (initialised_) MPI_Barrier(MPI_COMM_WORLD);
}

int Ranks::broadcast(int value) const {
  if (initialised_) MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return value;
}

std::vector<double> Ranks::broadcast(std::vector<double> values) const {
  if (!initialised_) return values;
  int n = static_cast<int>(values.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
  values.resize(static_cast<std::size_t>(n));
  if (n > 0) MPI_Bcast(values.data(), n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  return values;
}

int Ranks::max(int value) const {
  int largest = value;
  if (initialised_) MPI_Allreduce(&value, &largest, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return largest;
}

void Ranks::abort(int code) const {
  if (initialised_) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else

namespace {
int env_int(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : 0;
}
}  // namespace

Ranks::Ranks() {
  cores_ = machine_cores();
  cores_from_ = "the " + std::to_string(cores_) + " cores of this machine";
  // Several copies of a build without MPI would each run every point into the same OUT.
  const int world = std::max(env_int("OMPI_COMM_WORLD_SIZE"), env_int("PMI_SIZE"));
  if (world > 1)
    throw InputError("bagdem", "", "", "started as " + std::to_string(world) +
                                                 " MPI ranks, but this bagdem was built without MPI (BAGDEM_MPI=OFF): run it "
                                                 "without mpirun (it uses the node's cores by itself), or build with -DBAGDEM_MPI=ON");
}

Ranks::~Ranks() = default;
void Ranks::barrier() const {}
int Ranks::broadcast(int value) const { return value; }
std::vector<double> Ranks::broadcast(std::vector<double> values) const { return values; }
int Ranks::max(int value) const { return value; }
void Ranks::abort(int code) const { std::exit(code); }

#endif

}  // namespace bagdem::study
