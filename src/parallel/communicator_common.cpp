// SPDX-License-Identifier: BSD-3-Clause
// What the MPI and the serial Communicator share: typed errors across ranks, the stage runner,
// the collective-or-abort policy, the launcher check and the fault-injection hook.
#include <cstdlib>
#include <typeinfo>
#include <vrsph/core/error.hpp>
#include <vrsph/parallel/communicator.hpp>
#include "collective_errors.hpp"

namespace vrsph {

namespace detail {
ErrorKind kind_of(const std::exception& e) {
  // Most derived first: IoError is an InputError, ResourceError a ConfigError.
  if (dynamic_cast<const IoError*>(&e)) return Io;
  if (dynamic_cast<const InputError*>(&e)) return Input;
  if (dynamic_cast<const GeometryError*>(&e)) return Geometry;
  if (dynamic_cast<const NumericalError*>(&e)) return Numerical;
  if (dynamic_cast<const ResourceError*>(&e)) return Resource;
  if (dynamic_cast<const ConfigError*>(&e)) return Config;
  return Other;
}

std::string& last_agreed_message() {
  static std::string m;
  return m;
}

void rethrow(int kind, const std::string& msg) {
  switch (kind) {
    case Input: throw InputError(msg);
    case Io: throw IoError(msg);
    case Geometry: throw GeometryError(msg);
    case Numerical: throw NumericalError(msg);
    case Config: throw ConfigError(msg);
    case Resource: throw ResourceError(msg);
    default: throw std::runtime_error(msg);
  }
}

int exit_code(int kind) {
  switch (kind) {  // the CLI's exit codes (docs/errors.md)
    case Config:
    case Resource: return 2;
    case Input:
    case Io: return 3;
    case Geometry: return 4;
    case Numerical: return 5;
    default: return 70;
  }
}

Failure run_stage(const std::function<void()>& stage, bool pass_agreed) {
  try {
    stage();
  } catch (const std::exception& e) {
    if (pass_agreed && raised_on_every_rank(e)) throw;
    return {kind_of(e), e.what()};
  } catch (...) {
    return {Other, "unknown exception"};
  }
  return {};
}

}  // namespace detail

void rethrow_with_message(const std::exception& e, const std::string& message) {
  detail::rethrow(detail::kind_of(e), message);
}

bool raised_on_every_rank(const std::exception& e) { return detail::last_agreed_message() == e.what(); }

bool Communicator::launched_in_parallel() {
  // OpenMPI (mpirun), MPICH/Hydra and PMIx launchers set the world size in the environment.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "MPI_LOCALNRANKS"}) {
    const char* v = std::getenv(name);
    if (v && std::atoi(v) > 1) return true;
  }
  return false;
}

void collective_or_abort(const Communicator& comm, const std::function<void()>& stage) {
  if (!comm.distributed()) {
    stage();
    return;
  }
  const auto [kind, message] = detail::run_stage(stage, true);
  if (kind == detail::None) return;
  // Every rank failed alike: agree as `collective` does (all ranks are here, so the
  // communicator is free). Otherwise the others wait inside the stage: end them all.
  if (every_rank_stops_here(3.0)) {
    // Named copies: a lambda may capture structured bindings only from C++20 compilers
    // that implement P1091 (GCC 8+, clang 16+; the fuzz preset's clang 14 does not).
    collective(comm, [k = kind, m = message] { detail::rethrow(k, m); });
  }
  const int code = detail::exit_code(kind);
  const char* what = code == 2 ? "configuration error" : code == 3 ? "input error" : code == 4 ? "geometry error"
                     : code == 5 ? "numerical error" : "internal error";
  abort_all_ranks(comm, code, detail::concat("vrsph: ", what, " (rank ", comm.rank(), " of ", comm.size(),
                                             "; every rank stopped): ", message, "\n"));
}

void fault_point(const Communicator& comm, const char* stage) {
  static const std::string spec = [] {
    const char* v = std::getenv("VRSPH_INJECT_FAULT");
    return std::string(v ? v : "");
  }();
  if (spec.empty()) return;
  const auto at = spec.find('@');
  const std::string where = spec.substr(0, at);
  const int rank = at == std::string::npos ? 0 : std::atoi(spec.c_str() + at + 1);
  if (where == stage && rank == comm.rank())
    throw NumericalError(detail::concat("injected fault at stage '", stage, "' on rank ", rank, " (VRSPH_INJECT_FAULT)"));
}

}  // namespace vrsph
