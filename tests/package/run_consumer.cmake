# SPDX-License-Identifier: BSD-3-Clause
cmake_minimum_required(VERSION 3.25)  # (script mode: IN_LIST and other current policies)
# Builds and runs the consumer project against vrsph twice: installed (cmake --install into
# WORK_DIR/prefix, found through CMAKE_PREFIX_PATH) and straight from the build tree
# (vrsph_DIR=BUILD_DIR, nothing installed). The installed Python package, when the build has
# one, must import from the prefix and solve. KINDS: which of the two (default both).
if(NOT KINDS)
  set(KINDS installed build-tree)
endif()
file(REMOVE_RECURSE ${WORK_DIR})
if("installed" IN_LIST KINDS)
  execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix RESULT_VARIABLE rc OUTPUT_QUIET)
  if(rc)
    message(FATAL_ERROR "install failed: ${rc}")
  endif()
endif()
foreach(kind IN LISTS KINDS)
  if(kind STREQUAL "installed")
    set(where -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
  else()
    set(where -Dvrsph_DIR=${BUILD_DIR})
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build-${kind} ${where}
                          -DCMAKE_BUILD_TYPE=Release RESULT_VARIABLE rc)
  if(rc)
    message(FATAL_ERROR "consumer configure (${kind}) failed: ${rc}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/build-${kind} RESULT_VARIABLE rc)
  if(rc)
    message(FATAL_ERROR "consumer build (${kind}) failed: ${rc}")
  endif()
  foreach(program consumer consumer_bvp)
    execute_process(COMMAND ${WORK_DIR}/build-${kind}/${program} WORKING_DIRECTORY ${WORK_DIR}/build-${kind}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out)
    message(STATUS "${program} (${kind}) says: ${out}")
    if(rc)
      message(FATAL_ERROR "${program} (${kind}) failed: ${rc}")
    endif()
  endforeach()
endforeach()

set(python_dir ${WORK_DIR}/prefix/lib/python3/dist-packages)
if(PYTHON AND "installed" IN_LIST KINDS AND EXISTS ${python_dir}/vrsph)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${python_dir} ${PYTHON} -c
                          "import vrsph; c = vrsph.cloud.perturbed(dim=2, n=20); print(vrsph.solve(c, u='x*y + exp(x)').error_inf)"
                  WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "installed Python package says: ${out}")
  if(rc)
    message(FATAL_ERROR "the installed Python package failed: ${err}")
  endif()
endif()
