# engine/cmake/install.cmake — `cmake --install` rules: the mosaic CMake package and pkg-config file.
#
# Takes: the mosaic and mosaic_cli targets (engine/CMakeLists.txt includes this file after
# defining them). Gives, under the install prefix:
#   include/mosaic/*.hpp                    the public API (no xsimd or TBB type in it)
#   <libdir>/libmosaic.a                    the library, SIMD kernels folded in
#   bin/mosaic                              the command-line tool
#   <libdir>/cmake/mosaic/                  mosaicConfig.cmake, mosaicConfigVersion.cmake, targets:
#                                           find_package(mosaic CONFIG REQUIRED) -> mosaic::mosaic
#   <libdir>/pkgconfig/mosaic.pc            for builds that do not use CMake
#   share/mosaic/examples/                  the examples' sources (engine/examples), each a CMake
#                                           project that builds against this package
#
# Static, not shared: libmosaic is installed as a static archive on purpose. The tests,
# benchmarks and tools of this repository link the engine's internal stages (front/, raster/,
# reference/) directly; a shared library built with hidden visibility would hide them, and one
# built without would make every internal symbol ABI. A static archive keeps one build of the
# engine for both uses, and costs the consumer only the two private link dependencies
# (oneTBB, stb), which mosaicConfig.cmake and mosaic.pc find for it. The SIMD
# stages (the mosaic_simd_<isa> OBJECT libraries) are already inside the archive, so xsimd, which is
# header-only and used nowhere in the public headers, is not needed to link.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# Where the package files go, relative to the prefix.
set(MOSAIC_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/mosaic)
set(MOSAIC_INSTALL_PKGCONFIGDIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# The public headers use std::span: every consumer compiles as C++20 at least.
target_compile_features(mosaic PUBLIC cxx_std_20)

install(TARGETS mosaic EXPORT mosaicTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS mosaic_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/mosaic
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp")

install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/examples/
        DESTINATION ${CMAKE_INSTALL_DATADIR}/mosaic/examples)

install(EXPORT mosaicTargets NAMESPACE mosaic:: DESTINATION ${MOSAIC_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/mosaicConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/mosaicConfig.cmake
  INSTALL_DESTINATION ${MOSAIC_INSTALL_CMAKEDIR})
# Before 1.0 a minor release may change the API, so only the same major.minor satisfies a request.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/mosaicConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/mosaicConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/mosaicConfigVersion.cmake
        DESTINATION ${MOSAIC_INSTALL_CMAKEDIR})

# mosaic.pc names its prefix relative to its own folder (${pcfiledir}), so that an install moved
# or made with `cmake --install --prefix <elsewhere>` still points at itself.
if(IS_ABSOLUTE "${MOSAIC_INSTALL_PKGCONFIGDIR}")
  set(MOSAIC_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()
  file(RELATIVE_PATH _mosaic_pc_up "/prefix/${MOSAIC_INSTALL_PKGCONFIGDIR}" "/prefix")
  string(REGEX REPLACE "/$" "" _mosaic_pc_up "${_mosaic_pc_up}")
  set(MOSAIC_PC_PREFIX "\${pcfiledir}/${_mosaic_pc_up}")
  unset(_mosaic_pc_up)
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/mosaic.pc.in ${CMAKE_CURRENT_BINARY_DIR}/mosaic.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/mosaic.pc DESTINATION ${MOSAIC_INSTALL_PKGCONFIGDIR})
