# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... [-DCXX=...] -P install_test.cmake
#
# `cmake --install` into a fresh prefix, then from that prefix alone:
#  - the files a user and another project need are there;
#  - a tiny project (consumer/) finds the package with find_package(hmt_slam),
#    builds against it, and its program reads a log and the default config;
#  - the installed hmt-slam prints its version and its defaults (the
#    installed default.ini), and maps a ROS bag that the installed log-to-bag
#    wrote, with the MRPT maps, loading its plugins from the prefix's
#    lib/hmt-slam (LD_DEBUG=files shows which file dlopen() opened).
foreach(_var BUILD_DIR SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${_var})
    message(FATAL_ERROR "install_test.cmake: -D${_var}=... is required")
  endif()
endforeach()

function(run)
  cmake_parse_arguments(R "" "OUTPUT;ERROR;WORKING_DIRECTORY" "COMMAND" ${ARGN})
  if(NOT R_WORKING_DIRECTORY)
    set(R_WORKING_DIRECTORY "${WORK_DIR}")
  endif()
  execute_process(COMMAND ${R_COMMAND} WORKING_DIRECTORY "${R_WORKING_DIRECTORY}"
                  RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _err)
  if(NOT _rc EQUAL 0)
    string(REPLACE ";" " " _cmd "${R_COMMAND}")
    message(FATAL_ERROR "failed (${_rc}): ${_cmd}\n${_out}\n${_err}")
  endif()
  if(R_OUTPUT)
    set(${R_OUTPUT} "${_out}" PARENT_SCOPE)
  endif()
  if(R_ERROR)
    set(${R_ERROR} "${_err}" PARENT_SCOPE)
  endif()
endfunction()

function(expect_in haystack needle what)
  string(FIND "${haystack}" "${needle}" _at)
  if(_at EQUAL -1)
    message(FATAL_ERROR "${what}: '${needle}' not found in:\n${haystack}")
  endif()
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(P "${WORK_DIR}/prefix")
run(COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${P}")

foreach(_f bin/hmt-slam bin/hmt-partition bin/hmt-experiments bin/log-to-bag
           lib/hmt-slam/libhmt_io_mrpt.so lib/hmt-slam/libhmt_io_rosbag.so
           lib/hmt-slam/libhmt_io_mrpt_maps.so lib/libhmt_pipeline.a lib/libhmt_common.a
           lib/cmake/hmt_slam/hmt_slamConfig.cmake lib/cmake/hmt_slam/hmt_slamConfigVersion.cmake
           lib/cmake/hmt_slam/hmt_slamTargets.cmake include/hmt/version.h
           include/hmt/io/log_reader.h include/hmt/pipeline/default_config.h
           include/hmt/common/config.h share/hmt-slam/default.ini share/hmt-slam/report.py)
  if(NOT EXISTS "${P}/${_f}")
    message(FATAL_ERROR "not installed: ${_f}")
  endif()
endforeach()

# Another project, against the prefix only.
set(_gen_args)
if(CXX)
  list(APPEND _gen_args "-DCMAKE_CXX_COMPILER=${CXX}")
endif()
run(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}/tests/install/consumer"
            -B "${WORK_DIR}/consumer" "-DCMAKE_PREFIX_PATH=${P}" -DCMAKE_BUILD_TYPE=Release
            ${_gen_args})
run(COMMAND "${CMAKE_COMMAND}" --build "${WORK_DIR}/consumer" -j 2)
file(WRITE "${WORK_DIR}/tiny.log"
  "FLASER 5 1.5 1.6 1.7 1.8 1.9 0 0 0 0 0 0 1.0 host 1.0\n"
  "FLASER 5 1.4 1.6 1.7 1.8 1.9 0.1 0 0 0.1 0 0 1.1 host 1.1\n"
  "FLASER 5 1.3 1.6 1.7 1.8 1.9 0.2 0 0 0.2 0 0 1.2 host 1.2\n")
run(COMMAND "${WORK_DIR}/consumer/hmt_consumer" "${WORK_DIR}/tiny.log" OUTPUT _out)
expect_in("${_out}" "scans: 3\n" "consumer")
expect_in("${_out}" "first range: 1.50\n" "consumer")
expect_in("${_out}" "particles: 12\n" "consumer")
expect_in("${_out}" "resolution: 0.050\n" "consumer")
expect_in("${_out}" "hmt_consumer 0.1" "consumer")

# The installed programs.
foreach(_app hmt-slam hmt-partition hmt-experiments log-to-bag)
  run(COMMAND "${P}/bin/${_app}" --version OUTPUT _out)
  expect_in("${_out}" "${_app} 0.1" "${_app} --version")
endforeach()
run(COMMAND "${P}/bin/hmt-slam" config --dump OUTPUT _out)
file(READ "${P}/share/hmt-slam/default.ini" _ini)
if(NOT _out STREQUAL _ini)
  message(FATAL_ERROR "hmt-slam config --dump differs from the installed default.ini")
endif()
run(COMMAND "${P}/share/hmt-slam/report.py" --help OUTPUT _out)
expect_in("${_out}" "usage" "report.py --help")

run(COMMAND "${P}/bin/log-to-bag" --input "${SOURCE_DIR}/datasets/edmonton.log.gz"
            --output "${WORK_DIR}/edmonton.bag")
run(COMMAND "${CMAKE_COMMAND}" -E env --unset=HMT_IO_ROSBAG_PLUGIN
            --unset=HMT_IO_MRPT_MAPS_PLUGIN LD_DEBUG=files
            "${P}/bin/hmt-slam" run --quiet --input "${WORK_DIR}/edmonton.bag"
            --set input.max_steps=40 --set output.mrpt_maps=true --out "${WORK_DIR}/out"
    OUTPUT _out ERROR _err)
expect_in("${_out}" "processed 40 scans" "hmt-slam run on the bag")
expect_in("${_err}" "file=${P}/lib/hmt-slam/libhmt_io_rosbag.so" "the bag plugin from the prefix")
expect_in("${_err}" "file=${P}/lib/hmt-slam/libhmt_io_mrpt_maps.so" "the map plugin from the prefix")
foreach(_f map.pgm map.gridmap.gz keyframes.simplemap trajectory.tum)
  if(NOT EXISTS "${WORK_DIR}/out/${_f}")
    message(FATAL_ERROR "the installed hmt-slam wrote no ${_f}")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}")
