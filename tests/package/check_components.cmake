# SPDX-License-Identifier: BSD-3-Clause
cmake_minimum_required(VERSION 3.25)  # (script mode: IN_LIST and other current policies)
# find_package(vrsph COMPONENTS ...) against the build tree: every part this build has is found
# (any case), a part it lacks (and an unknown one) fails naming the VRSPH_WITH_ option.
# -DBUILD_DIR=<vrsph build> -DSOURCE_DIR=<components project> -DWORK_DIR=<scratch> -DBUILT=<parts> -DMISSING=<parts>
function(configure_with parts expect_ok)
  file(REMOVE_RECURSE ${WORK_DIR})
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR} -Dvrsph_DIR=${BUILD_DIR} "-DPARTS=${parts}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(expect_ok AND rc)
    message(FATAL_ERROR "find_package(vrsph COMPONENTS ${parts}) failed:\n${err}")
  endif()
  if(NOT expect_ok)
    string(REPLACE ";" " " err_flat "${err}")
    if(NOT rc)
      message(FATAL_ERROR "find_package(vrsph COMPONENTS ${parts}) succeeded though the build lacks ${parts}")
    endif()
    list(GET parts 0 first)
    string(TOUPPER "${first}" upper)
    if(NOT err MATCHES "vrsph was built without ${first}" OR NOT err MATCHES "VRSPH_WITH_${upper}=ON")
      message(FATAL_ERROR "find_package(vrsph COMPONENTS ${parts}): the message does not name the part:\n${err}")
    endif()
  endif()
  message(STATUS "COMPONENTS ${parts}: ${rc} as expected")
endfunction()

string(TOLOWER "${BUILT}" built_lower)
configure_with("${built_lower}" TRUE)
foreach(part IN LISTS MISSING ITEMS NOPE)
  configure_with("${part}" FALSE)
endforeach()
