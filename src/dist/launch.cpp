#include "dist/launch.h"

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#ifdef LANCER_WITH_MPI
#include "dist/mpi_channel.h"
#endif

namespace lancer {

namespace {

int positive_env(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr) return 0;
  int n = 0;
  const auto [end, error] = std::from_chars(value, value + std::strlen(value), n);
  return error == std::errc() && end == value + std::strlen(value) && n > 0 ? n : 0;
}

}  // namespace

int mpirun_world_size() { return positive_env("OMPI_COMM_WORLD_SIZE"); }
int mpirun_rank() { return positive_env("OMPI_COMM_WORLD_RANK"); }

std::unique_ptr<Channel> open_mpi_channel() {
  const int world = mpirun_world_size();
  if (world <= 1) return nullptr;
#ifdef LANCER_WITH_MPI
  return std::make_unique<MpiChannel>();
#else
  throw std::runtime_error("mpirun started " + std::to_string(world) +
                           " copies, but this lancer was built without Open MPI, so each would render the whole "
                           "image alone (install libopenmpi-dev and rebuild, or run lancer without mpirun)");
#endif
}

}  // namespace lancer
