// SPDX-License-Identifier: BSD-3-Clause
// Empty: the object library vrsph_test_pch exists to compile the test programs' precompiled
// header once (tests/CMakeLists.txt); every test program reuses it.
