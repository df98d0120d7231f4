# SPDX-License-Identifier: BSD-3-Clause
# Strict warnings for everything vrsph compiles itself (library, CLI, tests).
add_library(vrsph_warnings INTERFACE)
target_compile_options(vrsph_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion -Wnon-virtual-dtor
  -Wold-style-cast -Wcast-align -Woverloaded-virtual -Wdouble-promotion
  -Wimplicit-fallthrough -Werror=return-type
  # A target may opt out with the property VRSPH_NO_NULL_DEREFERENCE_WARNING (GCC 12's false
  # positives inside library headers: apps/vrsph/CMakeLists.txt says where).
  $<$<NOT:$<BOOL:$<TARGET_PROPERTY:VRSPH_NO_NULL_DEREFERENCE_WARNING>>>:-Wnull-dereference>)
if(NOT VRSPH_WITH_OPENMP)
  # Sequential builds (e.g. the sanitizer preset) ignore the OpenMP pragmas on purpose.
  target_compile_options(vrsph_warnings INTERFACE -Wno-unknown-pragmas)
endif()
