# hmt/version.h: the project's version (project(... VERSION ...)) and, when
# the source is a git checkout and git is installed, `git describe` of the
# commit configured (a tarball or an export has none: no error, no suffix).
set(HMT_GIT_DESCRIBE "")
find_package(Git QUIET)
if(GIT_FOUND AND EXISTS "${PROJECT_SOURCE_DIR}/.git")
  execute_process(
    COMMAND "${GIT_EXECUTABLE}" describe --always --dirty --tags
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
    OUTPUT_VARIABLE HMT_GIT_DESCRIBE
    OUTPUT_STRIP_TRAILING_WHITESPACE
    RESULT_VARIABLE _hmt_git_result
    ERROR_QUIET)
  if(NOT _hmt_git_result EQUAL 0)
    set(HMT_GIT_DESCRIBE "")
  endif()
endif()
configure_file("${CMAKE_CURRENT_LIST_DIR}/version.h.in"
               "${PROJECT_BINARY_DIR}/generated/hmt/version.h" @ONLY)

add_library(hmt_version INTERFACE)
target_include_directories(hmt_version INTERFACE
  $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated>
  $<INSTALL_INTERFACE:include>)
