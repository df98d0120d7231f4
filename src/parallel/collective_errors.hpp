// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: what the MPI and the serial Communicator share: the typed exceptions by a number
// that can cross ranks, the stage runner that catches them, and the message `collective`
// last agreed on (communicator_common.cpp).
#include <exception>
#include <functional>
#include <string>

namespace vrsph::detail {

// The typed exceptions by a number that can cross ranks (0: none).
enum ErrorKind : int { None = 0, Input, Io, Geometry, Numerical, Config, Resource, Other };

ErrorKind kind_of(const std::exception& e);
[[noreturn]] void rethrow(int kind, const std::string& message);
/// The CLI's exit code of an error kind (2 configuration, 3 input, 4 geometry, 5 numerical, 70 other).
int exit_code(int kind);
/// What `collective` last threw on every rank (one thread runs the collectives of a rank).
std::string& last_agreed_message();

/// What a stage threw on this rank (kind None: nothing).
struct Failure {
  int kind = None;
  std::string message;
};
/// Runs the stage and catches what it throws; pass_agreed: an exception `collective` already
/// raised on every rank goes on as it is.
Failure run_stage(const std::function<void()>& stage, bool pass_agreed);

}  // namespace vrsph::detail
