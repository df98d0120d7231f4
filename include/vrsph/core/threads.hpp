// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The OpenMP settings a process inherits from its environment, made safe before the first
// parallel region: libgomp reads OMP_NUM_THREADS and OMP_STACKSIZE when it is loaded and
// would try to start a million threads, or fail to start any, at the first parallel loop.
#include <string>

namespace vrsph {

/// Caps the thread count OMP_NUM_THREADS asked for at the number of cores (as --threads
/// does) and returns a one-line warning saying so, or "" when nothing was changed. Throws
/// ConfigError when OMP_STACKSIZE is not a stack size libgomp can give each thread (the
/// syntax of the OpenMP standard, at most 1 GiB). Call before any parallel work.
std::string sanitise_openmp_environment();

}  // namespace vrsph
