// simd/'s vocabulary (mask.hpp, records.hpp) compiled for one instruction set, as the stages are
// (simd/CMakeLists.txt's mosaic_isa_target()), behind plain functions on arrays:
// tests/test_simd_mask.cpp checks each set's against a scalar model on a CPU that runs it.
#include <cstdint>
#include <cstring>

#include "simd/isa.hpp"
#include "simd/lane_types.hpp"
#include "simd/records.hpp"

namespace mosaic::simd::MOSAIC_ISA {

inline constexpr int kMaxProbeLanes = 16;

namespace {
using T = LaneTypes<Arch>;
}  // namespace

int probe_lanes() { return T::L; }

int probe_double_lanes() { return T::kDLanes; }

std::uint32_t probe_nonzero_groups(std::uint64_t m) { return T::M::nonzero_groups(m); }

std::uint64_t probe_nonzero_nibbles(const std::uint64_t* words) {
  return T::M::nonzero_nibbles(words);
}

std::uint32_t probe_signs_int(const std::int32_t* v) {
  return T::M::signs(T::I::load_unaligned(v));
}

std::uint32_t probe_signs_double(const double* v) { return T::M::signs(T::D::load_unaligned(v)); }

// bits() of the masks that ints() and floats() make of b, and of a double comparison.
std::uint32_t probe_int_mask(std::uint32_t b) { return T::M::bits(T::M::ints(b)); }

std::uint32_t probe_float_mask(std::uint32_t b) { return T::M::bits(T::M::floats(b)); }

std::uint32_t probe_double_less(const double* a, const double* b) {
  return T::M::bits(T::D::load_unaligned(a) < T::D::load_unaligned(b));
}

void probe_to_float(const double* in, double* out) {
  T::M::to_float(T::D::load_unaligned(in)).store_unaligned(out);
}

// widen() of the kDLanes floats at `in`, and narrow() of the double lanes at `din` into `out`.
void probe_widen(const float* in, double* out) { T::M::widen(in).store_unaligned(out); }

void probe_narrow(const double* in, float* out) { T::M::narrow(out, T::D::load_unaligned(in)); }

void probe_compress_int(const std::int32_t* in, std::uint32_t b, std::int32_t* out) {
  T::M::compress(T::I::load_unaligned(in), b).store_unaligned(out);
}

void probe_compress_float(const float* in, std::uint32_t b, float* out) {
  T::M::compress(T::F::load_unaligned(in), b).store_unaligned(out);
}

// means<S>() of the S vectors laid end to end in `in`, for S = 4, 8, 16.
void probe_means(int S, const std::int32_t* in, std::int32_t* out) {
  T::I v[16];
  for (int i = 0; i < S; ++i) v[i] = T::I::load_unaligned(in + i * T::L);
  const T::I m = S == 4 ? T::M::means<4>(v) : S == 8 ? T::M::means<8>(v) : T::M::means<16>(v);
  m.store_unaligned(out);
}
void probe_permute(const std::int32_t* in, const std::int32_t* idx, std::int32_t* out) {
  T::M::permute(T::I::load_unaligned(in), T::I::load_unaligned(idx)).store_unaligned(out);
}

void probe_gather(const std::int32_t* base, const std::int32_t* idx, std::int32_t* out) {
  T::M::gather(base, T::I::load_unaligned(idx)).store_unaligned(out);
}

// store_samples4(), compiled with this set's flags.
void probe_store_samples4(std::uint32_t* words, std::uint32_t value, std::uint32_t bits) {
  store_samples4(words, value, bits);
}

// Records<>::columns() of the 32-byte records at rows[0 .. double lanes): words[j][l] is word j of
// record l; then each lane of word 0 split into its low and high floats, widened.
void probe_columns(const void* const* rows, std::uint64_t (*words)[kMaxProbeLanes], double* low,
                   double* high) {
  const void* r[T::kDLanes];
  for (int l = 0; l < T::kDLanes; ++l) r[l] = rows[l];
  T::D col[4];
  Records<Arch>::columns(r, col);
  for (int j = 0; j < 4; ++j) {
    alignas(64) double w[T::kDLanes];
    col[j].store_aligned(w);
    for (int l = 0; l < T::kDLanes; ++l) std::memcpy(&words[j][l], &w[l], sizeof w[l]);
  }
  Records<Arch>::low_floats(col[0]).store_unaligned(low);
  Records<Arch>::high_floats(col[0]).store_unaligned(high);
}

// Records<>::heads() of the records at rows[0 .. float lanes): words[j][l] is 32-bit word j of
// record l.
void probe_heads(const void* const* rows, std::uint32_t (*words)[kMaxProbeLanes]) {
  const void* r[T::L];
  for (int l = 0; l < T::L; ++l) r[l] = rows[l];
  T::F col[4];
  Records<Arch>::heads(r, col);
  for (int j = 0; j < 4; ++j) {
    alignas(64) float w[T::L];
    col[j].store_aligned(w);
    for (int l = 0; l < T::L; ++l) std::memcpy(&words[j][l], &w[l], sizeof w[l]);
  }
}

// Records<>::rows() of words made from double lanes: record l at out + l * 64 bytes gets
// int64s(ints[l]), pack_floats(a[l], b[l]), pack_ints(c[l], d[l]) and words 3..7 as given in
// more[j][l] (8 words a record, two blocks of four).
void probe_rows(const double* ints, const double* a, const double* b, const double* c,
                const double* d, const std::uint64_t (*more)[kMaxProbeLanes], void* out) {
  using D = T::D;
  D col[8];
  col[0] = Records<Arch>::int64s(D::load_unaligned(ints));
  col[1] = Records<Arch>::pack_floats(D::load_unaligned(a), D::load_unaligned(b));
  col[2] = Records<Arch>::pack_ints(D::load_unaligned(c), D::load_unaligned(d));
  for (int j = 3; j < 8; ++j) {
    alignas(64) double w[T::kDLanes];
    for (int l = 0; l < T::kDLanes; ++l) std::memcpy(&w[l], &more[j][l], sizeof w[l]);
    col[j] = D::load_aligned(w);
  }
  Records<Arch>::rows(col, 8, out, 64);
}

}  // namespace mosaic::simd::MOSAIC_ISA
