// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Internal: the failure of a parallel loop that a serial loop would have met first. Each
// iteration that throws records its index from its catch block; after the loop the exception
// of the lowest index is rethrown, so the message does not depend on the thread count or the
// schedule. Shared by the expression sampling (analysis/functions.cpp) and the checks of a
// caller's neighbour list (neighbours/user_list.cpp).
#include <exception>
#include <limits>
#include <vrsph/core/types.hpp>

namespace vrsph::detail {

class FirstFailure {
 public:
  /// Inside a catch block: the exception being handled, thrown by iteration `index`.
  void record(Index index) {
#pragma omp critical(vrsph_first_failure)
    if (index < index_) {
      index_ = index;
      error_ = std::current_exception();
    }
  }
  /// The lowest-index exception recorded, if any.
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  Index index_ = std::numeric_limits<Index>::max();
  std::exception_ptr error_;
};

}  // namespace vrsph::detail
