# Every dependency is a Debian package with a CMake config, or pkg-config files where it has
# none (see scripts/install-deps.sh).
find_package(glm REQUIRED)
find_package(TBB REQUIRED)
find_package(TinyGLTF REQUIRED)
find_package(nlohmann_json REQUIRED)
find_package(OpenEXR REQUIRED)
find_package(tinyobjloader REQUIRED)
find_package(CLI11 REQUIRED)
# KHR_draco_mesh_compression: Google's decoder (Debian's tinygltf is built without it).
find_package(draco CONFIG REQUIRED)
# EXT_meshopt_compression: the codec's own library (Debian ships its CMake config).
find_package(meshoptimizer CONFIG REQUIRED)
# EXT_texture_webp: Debian's libwebp has no CMake config, only pkg-config files.
find_package(PkgConfig REQUIRED)
pkg_check_modules(WebP REQUIRED IMPORTED_TARGET libwebp)

# stb ships no CMake config: Debian's libstb.so holds the implementations.
find_path(STB_INCLUDE_DIR stb_image.h PATH_SUFFIXES stb REQUIRED)
find_library(STB_LIBRARY stb REQUIRED)
add_library(lancer_stb INTERFACE)
target_include_directories(lancer_stb SYSTEM INTERFACE ${STB_INCLUDE_DIR})
target_link_libraries(lancer_stb INTERFACE ${STB_LIBRARY})

if(LANCER_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(LANCER_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
# Embree is optional: a benchmark baseline and a second test oracle, never linked into lancer.
find_package(embree 3 QUIET)
# Open MPI is optional: with it one render can be spread over processes and machines
# (mpirun -np N lancer render ...); without it lancer renders in one process and refuses to
# run as several copies under mpirun.
option(LANCER_MPI "Build the distributed render with Open MPI when it is installed" ON)
set(LANCER_WITH_MPI OFF)
if(LANCER_MPI)
  set(MPI_CXX_SKIP_MPICXX ON)  # the C API only: not the deprecated C++ bindings (libmpi_cxx)
  find_package(MPI COMPONENTS CXX QUIET)
  if(MPI_CXX_FOUND)
    set(LANCER_WITH_MPI ON)
  else()
    message(STATUS "Open MPI not found (libopenmpi-dev): lancer renders in one process only")
  endif()
endif()
