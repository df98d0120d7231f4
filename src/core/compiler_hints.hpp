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

// A hot kernel compiled twice on x86-64 with GCC, for x86-64-v3 (AVX2 + FMA) and the baseline,
// the loader picking one per CPU (the NNLS and simplex solves). Clang (the fuzz build) does not
// clone templates; the sanitizer builds compile one copy (the clones doubled the largest file of
// that CI stage). Only the instruction selection changes: results may differ in their last bits
// between CPUs (FMA contraction), never between thread counts on one machine.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__)
#define VRSPH_AVX2_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define VRSPH_AVX2_CLONES
#endif
