#include "cshapes/pipeline/distributed.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>

#include "cshapes/support/error.h"
#include "cshapes/pipeline/canonical_form_methods.h"

#ifdef CSHAPES_HAVE_MPI
#include <mpi.h>
#endif

namespace cshapes {

namespace {

#ifdef CSHAPES_HAVE_MPI

// Set by mpirun/mpiexec (OpenMPI, MPICH's hydra) and srun (PMI, PMIx): this process is one rank of a run.
bool started_by_mpi_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (const char* value = std::getenv(name); value && *value) return true;
  return false;
}

// MPI counts are ints: large buffers go in pieces of at most this many elements.
constexpr size_t kChunk = size_t{1} << 26;

class MpiCommunicator : public Communicator {
 public:
  MpiCommunicator() {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
      int provided = 0;
      MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
      std::atexit([] {
        int finalized = 0;
        MPI_Finalized(&finalized);
        if (!finalized) MPI_Finalize();
      });
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void barrier() const override { MPI_Barrier(MPI_COMM_WORLD); }
  void sum_to_all(double* values, size_t count) const override {
    for (size_t off = 0; off < count; off += kChunk)
      MPI_Allreduce(MPI_IN_PLACE, values + off, static_cast<int>(std::min(kChunk, count - off)), MPI_DOUBLE,
                    MPI_SUM, MPI_COMM_WORLD);
  }
  void sum_to_all(long* values, size_t count) const override {
    for (size_t off = 0; off < count; off += kChunk)
      MPI_Allreduce(MPI_IN_PLACE, values + off, static_cast<int>(std::min(kChunk, count - off)), MPI_LONG,
                    MPI_SUM, MPI_COMM_WORLD);
  }
  void sum_to_root(double* values, size_t count) const override {
    for (size_t off = 0; off < count; off += kChunk) {
      const int n = static_cast<int>(std::min(kChunk, count - off));
      if (rank_ == 0)
        MPI_Reduce(MPI_IN_PLACE, values + off, n, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
      else
        MPI_Reduce(values + off, nullptr, n, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    }
  }
  void broadcast_from_root(std::string& bytes) const override {
    unsigned long long size = bytes.size();
    MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    bytes.resize(static_cast<size_t>(size));
    for (size_t off = 0; off < bytes.size(); off += kChunk)
      MPI_Bcast(bytes.data() + off, static_cast<int>(std::min(kChunk, bytes.size() - off)), MPI_CHAR, 0,
                MPI_COMM_WORLD);
  }

 private:
  int rank_ = 0, size_ = 1;
};

#endif

}  // namespace

bool built_with_mpi() {
#ifdef CSHAPES_HAVE_MPI
  return true;
#else
  return false;
#endif
}

std::string mpi_launcher() {
#ifdef CSHAPES_MPIEXEC
  return CSHAPES_MPIEXEC;
#else
  return "";
#endif
}

const Communicator& world_communicator() {
#ifdef CSHAPES_HAVE_MPI
  if (started_by_mpi_launcher()) {
    static const MpiCommunicator world;
    return world;
  }
#endif
  return single_process();
}

void abort_all_ranks(int exit_code) {
#ifdef CSHAPES_HAVE_MPI
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (initialized && !finalized && world_communicator().size() > 1) MPI_Abort(MPI_COMM_WORLD, exit_code);
#else
  (void)exit_code;
#endif
}

int ranks_on_this_node() {
  for (const char* name : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"})
    if (const char* value = std::getenv(name); value && *value) {
      const long n = std::strtol(value, nullptr, 10);
      if (n >= 1 && n <= INT_MAX) return static_cast<int>(n);
    }
  return 1;
}

double canonical_form_cost(long vertices, const std::vector<std::string>& methods) {
  const double n = static_cast<double>(std::max(vertices, 2L));
  double cost = 0;
  for (const std::string& m : methods)
    cost += canonical_form_method(m).uses_geodesic_matrix ? n * n : n * std::log(n);
  return cost;
}

std::vector<int> canonical_form_owners(const std::vector<long>& vertices,
                                       const std::vector<std::string>& methods, int ranks) {
  std::vector<double> costs;
  for (long v : vertices) costs.push_back(canonical_form_cost(v, methods));
  return longest_first_owners(costs, ranks);
}

}  // namespace cshapes
