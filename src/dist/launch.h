// Whether this process is one of several that mpirun started, from the environment Open
// MPI gives its ranks; known without initialising MPI, and in a build without it.
#pragma once

#include <memory>

#include "dist/channel.h"

namespace lancer {

// The number of ranks mpirun started (OMPI_COMM_WORLD_SIZE), or 0 when not under mpirun.
int mpirun_world_size();

// This process's rank under mpirun (OMPI_COMM_WORLD_RANK), or 0 when not under mpirun.
int mpirun_rank();

// Under mpirun with more than one rank: the MPI channel between them (MPI is initialised
// here and finalised when it is destroyed). Otherwise null. Throws std::runtime_error under
// mpirun when built without MPI (each copy would render the whole image) or when MPI cannot
// start.
std::unique_ptr<Channel> open_mpi_channel();

}  // namespace lancer
