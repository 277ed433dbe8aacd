// simd/isa.hpp — the instruction set a simd/ stage source is being compiled for, checked against
// the compiler's flags, and its xsimd architecture.
//
// Part of simd/'s vocabulary: it includes nothing from engine/. simd/CMakeLists.txt builds each
// stage source once per instruction set, defining MOSAIC_ISA (the namespace: sse41, avx2 or
// avx512) and MOSAIC_ISA_<NAME>. Flags that enable less than the set would not build its
// intrinsics; flags that enable more would let the compiler emit instructions that fault on the
// CPUs this set is chosen for. Either fails here, at compile time.
#pragma once

#include <xsimd/xsimd.hpp>

#if defined(MOSAIC_ISA_SSE41)
#if !defined(__SSE4_1__) || defined(__AVX__)
#error "an sse41 stage must be compiled with -msse4.1 and without AVX"
#endif
namespace mosaic::simd::sse41 {
using Arch = xsimd::sse4_1;
}
#elif defined(MOSAIC_ISA_AVX2)
#if !defined(__AVX2__) || defined(__AVX512F__)
#error "an avx2 stage must be compiled with -mavx2 and without AVX-512"
#endif
namespace mosaic::simd::avx2 {
using Arch = xsimd::avx2;
}
#elif defined(MOSAIC_ISA_AVX512)
#if !defined(__AVX512F__) || !defined(__AVX512BW__) || !defined(__AVX512DQ__) || \
    !defined(__AVX512CD__) || !defined(__AVX512VL__)
#error \
    "an avx512 stage must be compiled with -mavx512f, -mavx512bw, -mavx512dq, -mavx512cd and -mavx512vl"
#endif
namespace mosaic::simd::avx512 {
using Arch = xsimd::avx512bw;
}
#else
#error \
    "simd/isa.hpp: build this source through simd/CMakeLists.txt, which names its instruction set"
#endif
