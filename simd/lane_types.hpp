// simd/lane_types.hpp — the lane types every SIMD stage of an instruction set works in.
//
// Part of simd/'s vocabulary (with mask.hpp): it includes nothing from engine/. The stages'
// templates (tile kernel, shading, resolve, hierarchical z) take their batch types from here.
#pragma once

#include <cstdint>
#include <xsimd/xsimd.hpp>

#include "simd/mask.hpp"

namespace mosaic::simd {

/// The batches of instruction set A: int32 and float lanes of one register, double lanes (half
/// as many), and the lane-mask helpers.
template <class A>
struct LaneTypes {
  using I = xsimd::batch<std::int32_t, A>;
  using F = xsimd::batch<float, A>;
  using D = xsimd::batch<double, A>;
  using M = Mask<A>;
  static constexpr int L = static_cast<int>(I::size);        ///< int32 and float lanes
  static constexpr int kDLanes = static_cast<int>(D::size);  ///< double lanes
  /// One bit per int32 lane.
  static constexpr std::uint32_t kLaneBits = L == 32 ? 0xffffffffu : (1u << L) - 1;
};

}  // namespace mosaic::simd
