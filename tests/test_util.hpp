// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Test helpers: EXPECT_THROW_MSG checks the exception type *and* its text.
#include <gtest/gtest.h>
#include <string>

#define EXPECT_THROW_MSG(statement, exception_type, substring)                                        \
  do {                                                                                                 \
    try {                                                                                              \
      statement;                                                                                       \
      ADD_FAILURE() << "expected " #exception_type " containing '" << (substring) << "', nothing thrown"; \
    } catch (const exception_type& e_) {                                                               \
      EXPECT_NE(std::string(e_.what()).find(substring), std::string::npos)                             \
          << "message was: " << e_.what() << "\nexpected to contain: " << (substring);                 \
    }                                                                                                  \
  } while (0)

// A test of a feature of an optional part (vrsph/core/features.hpp) is skipped, saying so, in a
// build without that part; tests/unit/core/test_features.cpp checks the refusal there.
#include <vrsph/core/features.hpp>
#define VRSPH_REQUIRE_PART(name)                                                                   \
  do {                                                                                             \
    if (!vrsph::built_with(name)) GTEST_SKIP() << "vrsph built without " name;                     \
  } while (0)
