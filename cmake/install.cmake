# `cmake --install build --prefix P`:
#   P/bin                     hmt-slam, hmt-partition, hmt-experiments, log-to-bag
#   P/lib                     the libraries (static), for other projects
#   P/lib/hmt-slam            the plugins (MRPT reader, MRPT map writer, ROS
#                             bags), found from bin/ (libs/io/src/plugin_loader.h)
#   P/include/hmt             every library's public headers and hmt/version.h
#   P/lib/cmake/hmt_slam      the CMake package: find_package(hmt_slam) gives
#                             the targets hmt_slam::hmt_<component>
#   P/share/hmt-slam          default.ini (the built-in defaults, documented)
#                             and report.py
include(CMakePackageConfigHelpers)

set(HMT_EXPORTED_LIBRARIES
  hmt_common hmt_sim hmt_area hmt_area_mrpt hmt_grid hmt_topology hmt_global_map
  hmt_io hmt_io_bag_writer hmt_rosbag_deps hmt_metric_slam hmt_alignment hmt_tsbi
  hmt_tlca hmt_hybrid hmt_framework hmt_checkpoint hmt_pipeline hmt_grouping hmt_experiments hmt_islands
  hmt_version)

install(TARGETS hmt-slam hmt-partition hmt-experiments log-to-bag
  RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
install(TARGETS ${HMT_EXPORTED_LIBRARIES}
  EXPORT hmt_slamTargets
  ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
  INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
install(TARGETS hmt_io_mrpt hmt_io_rosbag hmt_io_mrpt_maps
  LIBRARY DESTINATION "${HMT_INSTALL_PLUGINDIR}")

file(GLOB _hmt_include_dirs LIST_DIRECTORIES true "${PROJECT_SOURCE_DIR}/libs/*/include")
foreach(_dir ${_hmt_include_dirs})
  install(DIRECTORY "${_dir}/" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
          FILES_MATCHING PATTERN "*.h")
endforeach()
install(FILES "${PROJECT_BINARY_DIR}/generated/hmt/version.h"
        DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/hmt")

install(FILES "${PROJECT_SOURCE_DIR}/config/default.ini" DESTINATION "${HMT_INSTALL_DATADIR}")
install(PROGRAMS "${PROJECT_SOURCE_DIR}/scripts/report.py" DESTINATION "${HMT_INSTALL_DATADIR}")

install(EXPORT hmt_slamTargets
  NAMESPACE hmt_slam::
  DESTINATION "${HMT_INSTALL_CMAKEDIR}")
configure_package_config_file(
  "${CMAKE_CURRENT_LIST_DIR}/hmt_slamConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/hmt_slamConfig.cmake"
  INSTALL_DESTINATION "${HMT_INSTALL_CMAKEDIR}")
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/hmt_slamConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}"
  COMPATIBILITY SameMinorVersion)
install(FILES
  "${PROJECT_BINARY_DIR}/hmt_slamConfig.cmake"
  "${PROJECT_BINARY_DIR}/hmt_slamConfigVersion.cmake"
  DESTINATION "${HMT_INSTALL_CMAKEDIR}")
