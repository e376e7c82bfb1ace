#include "vpp/study/mpi.h"

#include <cstdlib>
#include <string>
#include <vector>

#ifdef VPPDEM_WITH_MPI
#include <mpi.h>
#endif

namespace vpp {

namespace {

[[maybe_unused]] bool mpi_active() {
#ifdef VPPDEM_WITH_MPI
    int init = 0, fin = 0;
    MPI_Initialized(&init);
    MPI_Finalized(&fin);
    return init && !fin;
#else
    return false;
#endif
}

}  // namespace

void mpi_barrier() {
#ifdef VPPDEM_WITH_MPI
    if (mpi_active()) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

std::string mpi_gather_text(const std::string& mine, int ranks) {
#ifdef VPPDEM_WITH_MPI
    if (mpi_active() && ranks > 1) {
        int rank = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        int len = int(mine.size());
        std::vector<int> lens(ranks), displs(ranks);
        MPI_Gather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
        std::string all;
        if (rank == 0) {
            int total = 0;
            for (int r = 0; r < ranks; ++r) {
                displs[r] = total;
                total += lens[r];
            }
            all.resize(std::size_t(total));
        }
        MPI_Gatherv(mine.data(), len, MPI_CHAR, all.data(), lens.data(), displs.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
        return rank == 0 ? all : mine;
    }
#endif
    (void)ranks;
    return mine;
}

int mpi_broadcast_int(int v) {
#ifdef VPPDEM_WITH_MPI
    if (mpi_active()) MPI_Bcast(&v, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
    return v;
}

void mpi_init_if_launched(int* argc, char*** argv, int* rank, int* ranks) {
    *rank = 0;
    *ranks = 1;
#ifdef VPPDEM_WITH_MPI
    // Only under a launcher: a plain run does not start the MPI runtime.
    const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") ||
                          std::getenv("PMIX_RANK") || std::getenv("MPI_LOCALNRANKS");
    if (!launched) return;
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, ranks);
#else
    (void)argc;
    (void)argv;
#endif
}

void mpi_abort_if_active(int code) {
#ifdef VPPDEM_WITH_MPI
    int ranks = 1;
    if (mpi_active()) {
        MPI_Comm_size(MPI_COMM_WORLD, &ranks);
        if (ranks > 1) MPI_Abort(MPI_COMM_WORLD, code);
    }
#endif
    (void)code;
}

void mpi_finalize() {
#ifdef VPPDEM_WITH_MPI
    if (mpi_active()) MPI_Finalize();
#endif
}

}  // namespace vpp
