// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Hints for the small fixed-size kernels of the stencil rows (the NNLS solves, the cubic
// correction). Private to the library.

// A helper (or lambda) the hot loop calls, forced inline: one left out of line keeps the loop
// around it from vectorising, and inside a target_clones function it would run baseline code.
#if defined(__GNUC__)
#define VRSPH_ALWAYS_INLINE __attribute__((always_inline))
#else
#define VRSPH_ALWAYS_INLINE
#endif

// A loop of the small solves unrolled up to 10 trips: the 9 x 9 systems become straight-line
// code the compiler schedules across their sqrt and division chains (measured per use, in the
// files that use it). GCC only: clang cannot unroll the loops that return early and warns
// (-Wpass-failed); its builds are the sanitizer and fuzz ones.
#if defined(__GNUC__) && !defined(__clang__)
#define VRSPH_UNROLL_SMALL _Pragma("GCC unroll 10")
#else
#define VRSPH_UNROLL_SMALL
#endif
