// MPI for `vppdem sweep` under mpirun: the ranks share the cases round-robin and rank 0
// gathers their outcomes. Every function is a no-op without MPI (VPPDEM_WITH_MPI) or outside a
// launcher, so the sweep code calls them unconditionally.
#pragma once

#include <string>

namespace vpp {

void mpi_init_if_launched(int* argc, char*** argv, int* rank, int* ranks);
void mpi_finalize();
void mpi_abort_if_active(int code);  // after an error on one rank: stop them all
void mpi_barrier();
// Rank 0 receives every rank's text, concatenated in rank order (the others get their own back).
std::string mpi_gather_text(const std::string& mine, int ranks);
// Rank 0's value on every rank.
int mpi_broadcast_int(int v);

}  // namespace vpp
