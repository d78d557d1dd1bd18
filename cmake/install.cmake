# `cmake --install BUILD --prefix P` installs:
#   P/bin/bpm-*                         the tools (static runtime, as built)
#   P/include/bpm/*.h, bpm/version.h    the public headers (self-contained: no CGAL, Eigen, HDF5)
#   P/lib/libbpm.so.0 -> .so.0.1.0      the shared library (SONAME libbpm.so.<major>)
#   P/lib/cmake/bpm/                    CMake package: find_package(bpm) -> bpm::bpm
#   P/lib/pkgconfig/bpm.pc              pkg-config --cflags --libs bpm
# The static archive is not installed: it carries the static HDF5/GMP link of the tools.
# (lib is CMAKE_INSTALL_LIBDIR: lib/<multiarch> when the prefix is /usr.)
include(CMakePackageConfigHelpers)

set(BPM_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/bpm)
set(BPM_PKGCONFIG_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

install(TARGETS bpm_shared EXPORT bpmTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/libbpm/include/bpm DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h" PATTERN "*.hh")  # .hh: DUNE adapters (bpm/dune/)
install(FILES ${PROJECT_BINARY_DIR}/libbpm/generated/bpm/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/bpm)

install(EXPORT bpmTargets NAMESPACE bpm:: DESTINATION ${BPM_CMAKE_INSTALL_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/bpmConfig.cmake.in
  ${PROJECT_BINARY_DIR}/cmake/bpmConfig.cmake INSTALL_DESTINATION ${BPM_CMAKE_INSTALL_DIR})
# 0.x: the SONAME is libbpm.so.0, so any 0.y satisfies a request for 0.x (x <= y).
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cmake/bpmConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cmake/bpmConfig.cmake ${PROJECT_BINARY_DIR}/cmake/bpmConfigVersion.cmake
        DESTINATION ${BPM_CMAKE_INSTALL_DIR})

# bpm.pc is relocatable: its prefix is found from the .pc file's own directory, so it is
# right for any `--prefix` given at install time.
file(RELATIVE_PATH BPM_PC_PREFIX_FROM_PCDIR /prefix/${BPM_PKGCONFIG_INSTALL_DIR} /prefix)
string(REGEX REPLACE "/$" "" BPM_PC_PREFIX_FROM_PCDIR "${BPM_PC_PREFIX_FROM_PCDIR}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/bpm.pc.in ${PROJECT_BINARY_DIR}/cmake/bpm.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/cmake/bpm.pc DESTINATION ${BPM_PKGCONFIG_INSTALL_DIR})
