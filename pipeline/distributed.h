// Distributed runs under MPI: the communicator of the processes `mpirun -np R cshapes …` started, and the
// helpers that split the pipeline's expensive stages (canonical forms, pair alignments) across them.
//
// world_communicator() is MPI_COMM_WORLD when this build has MPI (CSHAPES_HAVE_MPI, CMake found it) and
// the process was started by an MPI launcher (mpirun/mpiexec/srun set OMPI_COMM_WORLD_SIZE, PMIX_RANK or
// PMI_RANK); otherwise the one-process communicator, without initialising MPI at all, so the same binary
// runs alone exactly as before. MPI is initialised on the first call (MPI_THREAD_FUNNELED: only the main
// thread talks to MPI; OpenMP threads work in between) and finalised at exit.
//
// The protocol of every distributed stage: each rank takes its share of the items, computes the missing
// ones into the shared on-disk cache (its only writes), then the results meet on rank 0, which writes every
// output. The cache is the shared state: a run killed at any point and started again with any R recomputes
// nothing that was stored. Ranks on several nodes need the cache on a file system they all see.
// Cost: the collectives move O(N²) doubles once (the distance matrices, summed onto rank 0) and O(N²) bytes
// (which pairs are missing); everything else is O(N).
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/communicator.h"

namespace cshapes {

// The communicator of this process's run: MPI_COMM_WORLD under an MPI launcher (in an MPI build), else rank
// 0 of 1. Lives until the process exits.
const Communicator& world_communicator();
// Whether this build can run distributed (CMake found MPI).
bool built_with_mpi();
// The MPI launcher CMake found with MPI (e.g. /usr/bin/mpiexec), "" without MPI: for tests and scripts.
std::string mpi_launcher();
// Ends the run at once on every rank with this exit code (MPI_Abort), for an error that only this rank saw
// while the others may be waiting in a collective call. One process: returns without doing anything.
void abort_all_ranks(int exit_code);
// Processes of this run on this node (mpirun's OMPI_COMM_WORLD_LOCAL_SIZE and the like), 1 alone: the
// default OpenMP thread count divides the cores among them.
int ranks_on_this_node();

// The expected cost of canonizing a mesh of n vertices by each of `methods`, in arbitrary units comparable
// between meshes: n² for a method that uses the all-pairs geodesic matrix (cmds, smacof), else n log n
// (Coulomb, per iteration). Throws for an unknown method.
double canonical_form_cost(long vertices, const std::vector<std::string>& methods);

// Which rank canonizes which shape: longest-first greedy over canonical_form_cost (support/communicator.h).
std::vector<int> canonical_form_owners(const std::vector<long>& vertices,
                                       const std::vector<std::string>& methods, int ranks);

}  // namespace cshapes
