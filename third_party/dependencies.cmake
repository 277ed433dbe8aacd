# CMake glue for mosaic's dependencies. Every one comes from a Debian package installed by
# third_party/install-deps.sh; nothing is fetched at configure or build time.

find_package(TBB REQUIRED)               # libtbb-dev
find_package(xsimd REQUIRED)             # libxsimd-dev
find_package(glm REQUIRED)               # libglm-dev
find_package(CLI11 REQUIRED)             # libcli11-dev
find_package(nlohmann_json REQUIRED)     # nlohmann-json3-dev
find_package(PkgConfig REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)   # libstb-dev ships a compiled libstb
pkg_check_modules(FFTW3 REQUIRED IMPORTED_TARGET fftw3)  # libfftw3-dev: spectra in mosaic report
pkg_check_modules(GMPXX REQUIRED IMPORTED_TARGET gmpxx)  # libgmp-dev: exact rational areas (mosaic report)

if(MOSAIC_BUILD_TESTS)
  find_package(GTest REQUIRED)           # libgtest-dev
endif()
if(MOSAIC_BUILD_BENCH)
  find_package(benchmark REQUIRED)       # libbenchmark-dev
endif()

# GLM's Debian config names its target glm::glm; older configs named it glm.
if(NOT TARGET glm::glm AND TARGET glm)
  add_library(glm::glm ALIAS glm)
endif()
