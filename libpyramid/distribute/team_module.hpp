// The MPI module: the MPI world behind a library of its own (libpyramid_mpi.so, distribute/mpi/),
// loaded with dlopen only when mpirun started the program. Open MPI is eight shared libraries
// whose loading and start-up cost every run about 8 ms, most of a small job's start-up; a run
// without mpirun never loads them.
//
// The interface is plain C++ between two parts of one build (same compiler and standard
// library), as the image I/O module's (input/image_io_module.hpp).
#pragma once
#include "libpyramid/distribute/team.hpp"

namespace pyramid {

struct TeamModule {
    // kTeamModuleAbi of the build that made the module; a module from another build is refused.
    int abi = 0;
    // Joins the MPI world (MPI_Init_thread, MPI_THREAD_FUNNELED): the team of its ranks.
    Team* (*join)(int* argc, char*** argv) = nullptr;
    // Leaves it (MPI_Finalize); the team is gone.
    void (*leave)() = nullptr;
};

// Bumped whenever TeamModule or Team change.
inline constexpr int kTeamModuleAbi = 1;

} // namespace pyramid

// The module's entry point.
extern "C" const pyramid::TeamModule* pyramid_team_module();
