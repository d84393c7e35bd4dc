# What `cmake --install` puts under the prefix, and the Debian package `cpack -G DEB` makes of it
# (docs/install.md):
#   bin/iaa, bin/iaa-viz                          the commands
#   lib/iaa/libiaa_vtk.so                         the iaa command's VTK plugin (viz/plugin_api.h)
#   lib/libiaa_<module>.a, include/iaa/<module>/  the library modules and their headers
#   lib/cmake/iaa/                                the package: find_package(iaa), iaa::iaa ...
#   share/iaa/scenes/*.toml                       the bundled scenes (the demo's teardrop)
#   lib/python3.X/dist-packages/iaa/              the Python module (tools/python/CMakeLists.txt)
# The binaries' own rules sit beside their targets (tools/, viz/, tools/python/).
include(CMakePackageConfigHelpers)

set(IAA_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/iaa)
set_target_properties(iaa PROPERTIES EXPORT_NAME iaa)
set_target_properties(iaa_options PROPERTIES EXPORT_NAME options)
get_property(iaa_module_targets GLOBAL PROPERTY IAA_MODULES)  # core ... compare, app
# dist (MPI, for the iaa command under mpirun) is not part of the installed library.
list(REMOVE_ITEM iaa_module_targets dist)
list(TRANSFORM iaa_module_targets PREPEND iaa_)
install(TARGETS iaa iaa_options ${iaa_module_targets} EXPORT iaaTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/libiaa/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/iaa
  COMPONENT dev FILES_MATCHING PATTERN "*.h" PATTERN dist EXCLUDE)
install(EXPORT iaaTargets NAMESPACE iaa:: DESTINATION ${IAA_CMAKE_DIR} COMPONENT dev)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/iaaConfig.cmake.in
  ${CMAKE_BINARY_DIR}/iaaConfig.cmake INSTALL_DESTINATION ${IAA_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/iaaConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/iaaConfig.cmake ${CMAKE_BINARY_DIR}/iaaConfigVersion.cmake
  DESTINATION ${IAA_CMAKE_DIR} COMPONENT dev)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/iaa/scenes
  FILES_MATCHING PATTERN "*.toml")

# One Debian package with everything; its run-time dependencies come from the binaries
# (dpkg-shlibdeps), the libraries' build dependencies are suggested.
set(CPACK_PACKAGE_NAME iaa)
set(CPACK_PACKAGE_VENDOR "iaa")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "guaranteed rendering, enclosure and meshing of implicit surfaces with interval arithmetic")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "iaa maintainers <iaa@localhost>")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3, python3-numpy")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libboost-dev, libtbb-dev, libpng-dev, nlohmann-json3-dev, \
libtomlplusplus-dev, libcgal-dev, libopenmesh-dev")
include(CPack)
