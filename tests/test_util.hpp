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
