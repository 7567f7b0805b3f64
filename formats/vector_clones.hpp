// PYRAMID_VECTOR_CLONES: compiles a hot loop twice, for baseline x86-64 (SSE2) and for AVX2,
// and picks one when the program starts (GCC and clang `target_clones`, resolved by an ifunc).
// Code written in vectors that must fit one register (the DXT colour fit) picks its width at run
// time instead (dxt_colour_fit.cpp): the same source at 4, 8 or 16 lanes.
//
// Why the results are the same bytes on every machine: the clones differ only in vector width.
// Each float or double operation is correctly rounded by IEEE 754 whatever instruction performs
// it; contraction into fused multiply-adds is off for the whole build (-ffp-contract=off; "avx2"
// does not enable FMA instructions either) and nothing is reassociated (no fast-math), so every
// sample goes through the same operations in the same order in every clone.
#pragma once

#if defined(__x86_64__) && defined(__ELF__) && !defined(PYRAMID_NO_VECTOR_CLONES)
#define PYRAMID_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#define PYRAMID_VECTOR_CLONES_ON 1 // for --version
#else
#define PYRAMID_VECTOR_CLONES
#define PYRAMID_VECTOR_CLONES_ON 0
#endif
