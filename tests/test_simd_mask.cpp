// simd/mask.hpp and simd/records.hpp, the vocabulary every SIMD stage is written in, on each
// instruction set this build compiles and this CPU runs, against scalar models: lane groups
// holding a bit, sign bits, masks to and from lanes, rounding to float, compress, a pixel's bits
// of four masks, gathers, four samples stored under a mask, and records (whole, or their first 16
// bytes) transposed into lanes. The stages use these at every block and batch, so an error here
// would show only as a wrong image somewhere; here it shows as the helper and the input that broke.
// The helpers are compiled per set by tests/isa/mask_probe.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "mosaic/mosaic.hpp"

#define MOSAIC_DECLARE_PROBES(ns)                                                           \
  namespace mosaic::simd::ns {                                                              \
  int probe_lanes();                                                                        \
  int probe_double_lanes();                                                                 \
  std::uint32_t probe_nonzero_groups(std::uint64_t m);                                      \
  std::uint64_t probe_nonzero_nibbles(const std::uint64_t* words);                          \
  std::uint32_t probe_signs_int(const std::int32_t* v);                                     \
  std::uint32_t probe_signs_double(const double* v);                                        \
  std::uint32_t probe_int_mask(std::uint32_t b);                                            \
  std::uint32_t probe_float_mask(std::uint32_t b);                                          \
  std::uint32_t probe_double_less(const double* a, const double* b);                        \
  void probe_to_float(const double* in, double* out);                                       \
  void probe_widen(const float* in, double* out);                                           \
  void probe_narrow(const double* in, float* out);                                          \
  void probe_compress_int(const std::int32_t* in, std::uint32_t b, std::int32_t* out);      \
  void probe_compress_float(const float* in, std::uint32_t b, float* out);                  \
  void probe_means(int S, const std::int32_t* in, std::int32_t* out);                       \
  void probe_permute(const std::int32_t* in, const std::int32_t* idx, std::int32_t* out);   \
  void probe_gather(const std::int32_t* base, const std::int32_t* idx, std::int32_t* out);  \
  void probe_store_samples4(std::uint32_t* words, std::uint32_t value, std::uint32_t bits); \
  void probe_columns(const void* const* rows, std::uint64_t (*words)[16], double* low,      \
                     double* high);                                                         \
  void probe_heads(const void* const* rows, std::uint32_t (*words)[16]);                    \
  void probe_rows(const double* ints, const double* a, const double* b, const double* c,    \
                  const double* d, const std::uint64_t (*more)[16], void* out);             \
  }

#if MOSAIC_PROBE_SSE41
MOSAIC_DECLARE_PROBES(sse41)
#endif
#if MOSAIC_PROBE_AVX2
MOSAIC_DECLARE_PROBES(avx2)
#endif
#if MOSAIC_PROBE_AVX512
MOSAIC_DECLARE_PROBES(avx512)
#endif

namespace {

using mosaic::Isa;

struct Probe {
  Isa isa;
  int (*lanes)();
  int (*double_lanes)();
  std::uint32_t (*nonzero_groups)(std::uint64_t);
  std::uint64_t (*nonzero_nibbles)(const std::uint64_t*);
  std::uint32_t (*signs_int)(const std::int32_t*);
  std::uint32_t (*signs_double)(const double*);
  std::uint32_t (*int_mask)(std::uint32_t);
  std::uint32_t (*float_mask)(std::uint32_t);
  std::uint32_t (*double_less)(const double*, const double*);
  void (*to_float)(const double*, double*);
  void (*widen)(const float*, double*);
  void (*narrow)(const double*, float*);
  void (*compress_int)(const std::int32_t*, std::uint32_t, std::int32_t*);
  void (*compress_float)(const float*, std::uint32_t, float*);
  void (*means)(int, const std::int32_t*, std::int32_t*);
  void (*permute)(const std::int32_t*, const std::int32_t*, std::int32_t*);
  void (*gather)(const std::int32_t*, const std::int32_t*, std::int32_t*);
  void (*store_samples4)(std::uint32_t*, std::uint32_t, std::uint32_t);
  void (*columns)(const void* const*, std::uint64_t (*)[16], double*, double*);
  void (*heads)(const void* const*, std::uint32_t (*)[16]);
  void (*rows)(const double*, const double*, const double*, const double*, const double*,
               const std::uint64_t (*)[16], void*);
};

#define MOSAIC_PROBE(ns, isa)                                                              \
  Probe {                                                                                  \
    isa, &mosaic::simd::ns::probe_lanes, &mosaic::simd::ns::probe_double_lanes,            \
        &mosaic::simd::ns::probe_nonzero_groups, &mosaic::simd::ns::probe_nonzero_nibbles, \
        &mosaic::simd::ns::probe_signs_int, &mosaic::simd::ns::probe_signs_double,         \
        &mosaic::simd::ns::probe_int_mask, &mosaic::simd::ns::probe_float_mask,            \
        &mosaic::simd::ns::probe_double_less, &mosaic::simd::ns::probe_to_float,           \
        &mosaic::simd::ns::probe_widen, &mosaic::simd::ns::probe_narrow,                   \
        &mosaic::simd::ns::probe_compress_int, &mosaic::simd::ns::probe_compress_float,    \
        &mosaic::simd::ns::probe_means, &mosaic::simd::ns::probe_permute,                  \
        &mosaic::simd::ns::probe_gather, &mosaic::simd::ns::probe_store_samples4,          \
        &mosaic::simd::ns::probe_columns, &mosaic::simd::ns::probe_heads,                  \
        &mosaic::simd::ns::probe_rows                                                      \
  }

// The probes of every set this build compiles and this CPU runs.
std::vector<Probe> runnable_probes() {
  std::vector<Probe> all;
#if MOSAIC_PROBE_SSE41
  all.push_back(MOSAIC_PROBE(sse41, Isa::kSse41));
#endif
#if MOSAIC_PROBE_AVX2
  all.push_back(MOSAIC_PROBE(avx2, Isa::kAvx2));
#endif
#if MOSAIC_PROBE_AVX512
  all.push_back(MOSAIC_PROBE(avx512, Isa::kAvx512));
#endif
  std::vector<Probe> runnable;
  const std::vector<Isa> available = mosaic::available_isas();
  for (const Probe& p : all)
    for (const Isa a : available)
      if (a == p.isa) runnable.push_back(p);
  return runnable;
}

constexpr int kMaxLanes = 16;

class SimdMask : public testing::Test {
 protected:
  void SetUp() override {
    probes_ = runnable_probes();
    if (probes_.empty()) GTEST_SKIP() << "no SIMD instruction set built that this CPU runs";
  }
  std::vector<Probe> probes_;
  std::mt19937_64 rng_{20261205};
};

TEST_F(SimdMask, LaneCountsMatchTheSet) {
  for (const Probe& p : probes_) {
    std::printf("probing %s\n", std::string(mosaic::to_string(p.isa)).c_str());
    const int want = p.isa == Isa::kSse41 ? 4 : p.isa == Isa::kAvx2 ? 8 : 16;
    EXPECT_EQ(p.lanes(), want) << mosaic::to_string(p.isa);
    EXPECT_EQ(p.double_lanes(), want / 2) << mosaic::to_string(p.isa);
  }
}

// Bit j where bits L j .. L j + L - 1 of m hold a set bit: every single bit, every group alone
// full, and random words, sparse and dense.
TEST_F(SimdMask, NonzeroGroupsMarksEachGroupHoldingABit) {
  for (const Probe& p : probes_) {
    const int L = p.lanes(), groups = 64 / L;
    const std::uint64_t group = L == 64 ? ~0ull : (1ull << L) - 1;
    const auto model = [&](std::uint64_t m) {
      std::uint32_t g = 0;
      for (int j = 0; j < groups; ++j) g |= std::uint32_t{((m >> (L * j)) & group) != 0} << j;
      return g;
    };
    std::vector<std::uint64_t> words{0, ~0ull};
    for (int b = 0; b < 64; ++b) words.push_back(1ull << b);
    for (int j = 0; j < groups; ++j) words.push_back(group << (L * j));
    for (int k = 0; k < 2000; ++k) {
      words.push_back(rng_());
      words.push_back(rng_() & rng_() & rng_() & rng_());
    }
    for (const std::uint64_t m : words)
      ASSERT_EQ(p.nonzero_groups(m), model(m)) << mosaic::to_string(p.isa) << " m=" << m;
  }
}

// Bit p where nibble p of four words laid end to end (a 4x block's samples, pixel-major) holds a
// set bit: every single bit, every nibble alone full, and random words, sparse and dense.
// Lane l: base[idx[l]], for indices anywhere in a table (repeated, and at both ends).
TEST_F(SimdMask, GatherReadsEachLanesWord) {
  std::array<std::int32_t, 64> base{};
  for (std::size_t i = 0; i < base.size(); ++i)
    base[i] = static_cast<std::int32_t>(0x5a000000u + 977u * i);
  for (const Probe& p : probes_) {
    const int L = p.lanes();
    for (int k = 0; k < 500; ++k) {
      std::int32_t idx[kMaxLanes], got[kMaxLanes];
      for (int l = 0; l < L; ++l)
        idx[l] = k == 0 ? (l % 2 ? 63 : 0) : static_cast<std::int32_t>(rng_() % base.size());
      p.gather(base.data(), idx, got);
      for (int l = 0; l < L; ++l)
        ASSERT_EQ(got[l], base[static_cast<std::size_t>(idx[l])])
            << mosaic::to_string(p.isa) << " lane " << l << " index " << idx[l];
    }
  }
}

// A shaded pixel's colour into the samples that passed (a 4-bit mask; higher bits ignored),
// the other words of the four and their neighbours left alone, at every alignment of a word.
TEST_F(SimdMask, StoreSamples4WritesExactlyTheSamplesThatPassed) {
  for (const Probe& p : probes_)
    for (std::uint32_t bits = 0; bits < 64; ++bits)
      for (int at = 1; at <= 4; ++at) {
        std::array<std::uint32_t, 9> words{}, model{};
        for (std::size_t i = 0; i < words.size(); ++i)
          words[i] = model[i] = 0x01010101u * static_cast<std::uint32_t>(i + 1);
        const std::uint32_t value = 0xa5c30000u | bits;
        for (int k = 0; k < 4; ++k)
          if (bits >> k & 1u) model[static_cast<std::size_t>(at + k)] = value;
        p.store_samples4(words.data() + at, value, bits);
        ASSERT_EQ(words, model) << mosaic::to_string(p.isa) << " bits " << bits << " at " << at;
      }
}

TEST_F(SimdMask, NonzeroNibblesMarksEachPixelHoldingASample) {
  const auto model = [](const std::uint64_t* w) {
    std::uint64_t pixels = 0;
    for (int p = 0; p < 64; ++p)
      pixels |= std::uint64_t{((w[p / 16] >> (4 * (p % 16))) & 0xfu) != 0} << p;
    return pixels;
  };
  std::vector<std::array<std::uint64_t, 4>> cases{{0, 0, 0, 0}, {~0ull, ~0ull, ~0ull, ~0ull}};
  for (int b = 0; b < 256; ++b) {
    std::array<std::uint64_t, 4> one{};
    one[b / 64] = 1ull << (b % 64);
    cases.push_back(one);
  }
  for (int p = 0; p < 64; ++p) {
    std::array<std::uint64_t, 4> full{};
    full[p / 16] = 0xfull << (4 * (p % 16));
    cases.push_back(full);
  }
  for (int k = 0; k < 2000; ++k) {
    cases.push_back({rng_(), rng_(), rng_(), rng_()});
    std::array<std::uint64_t, 4> sparse{};
    for (std::uint64_t& w : sparse) w = rng_() & rng_() & rng_() & rng_();
    cases.push_back(sparse);
  }
  for (const Probe& p : probes_)
    for (const auto& w : cases)
      ASSERT_EQ(p.nonzero_nibbles(w.data()), model(w.data()))
          << mosaic::to_string(p.isa) << " words " << w[0] << " " << w[1] << " " << w[2] << " "
          << w[3];
}

TEST_F(SimdMask, SignsAreTheLanesSignBits) {
  const std::int32_t ints[] = {0,
                               1,
                               -1,
                               std::numeric_limits<std::int32_t>::min(),
                               std::numeric_limits<std::int32_t>::max(),
                               -256,
                               256};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double doubles[] = {0.0, -0.0, 1.0, -1.0, inf, -inf, nan, -nan, 1e-310, -1e-310};
  for (const Probe& p : probes_) {
    const int L = p.lanes(), DL = p.double_lanes();
    for (int k = 0; k < 500; ++k) {
      std::int32_t v[kMaxLanes];
      std::uint32_t want = 0;
      for (int l = 0; l < L; ++l) {
        v[l] = ints[rng_() % std::size(ints)];
        want |= std::uint32_t{v[l] < 0} << l;
      }
      ASSERT_EQ(p.signs_int(v), want) << mosaic::to_string(p.isa);
      double d[kMaxLanes];
      std::uint32_t dwant = 0;
      for (int l = 0; l < DL; ++l) {
        d[l] = doubles[rng_() % std::size(doubles)];
        dwant |= std::uint32_t{std::signbit(d[l])} << l;
      }
      ASSERT_EQ(p.signs_double(d), dwant) << mosaic::to_string(p.isa);
    }
  }
}

// ints() and floats() set exactly the lanes of b, for every b; a double comparison's mask is the
// comparison lane by lane, NaN included.
TEST_F(SimdMask, MasksRoundTripAndCompare) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Probe& p : probes_) {
    const int L = p.lanes(), DL = p.double_lanes();
    for (std::uint32_t b = 0; b < (1u << L); ++b) {
      ASSERT_EQ(p.int_mask(b), b) << mosaic::to_string(p.isa);
      ASSERT_EQ(p.float_mask(b), b) << mosaic::to_string(p.isa);
    }
    for (int k = 0; k < 500; ++k) {
      double a[kMaxLanes], c[kMaxLanes];
      std::uint32_t want = 0;
      for (int l = 0; l < DL; ++l) {
        a[l] = static_cast<double>(rng_() % 5) - 2.0;
        c[l] = rng_() % 7 == 0 ? nan : static_cast<double>(rng_() % 5) - 2.0;
        want |= std::uint32_t{a[l] < c[l]} << l;
      }
      ASSERT_EQ(p.double_less(a, c), want) << mosaic::to_string(p.isa);
    }
  }
}

// Each lane rounded to float as a scalar conversion rounds it (to nearest, ties to even), then
// widened back: halfway cases, float's subnormals and overflow included.
TEST_F(SimdMask, ToFloatRoundsLikeTheScalarConversion) {
  for (const Probe& p : probes_) {
    const int DL = p.double_lanes();
    for (int k = 0; k < 4000; ++k) {
      double in[kMaxLanes], out[kMaxLanes];
      // Around float's overflow: FLT_MAX plus half its last place (2^103) rounds to infinity,
      // a double step less to FLT_MAX.
      const double flt_max = std::numeric_limits<float>::max();
      const double overflow[] = {flt_max,
                                 -flt_max,
                                 flt_max + std::ldexp(1.0, 103),
                                 -(flt_max + std::ldexp(1.0, 103)),
                                 std::nextafter(flt_max + std::ldexp(1.0, 103), 0.0),
                                 -std::nextafter(flt_max + std::ldexp(1.0, 103), 0.0),
                                 std::nextafter(flt_max, 1e300),
                                 std::numeric_limits<double>::infinity(),
                                 std::numeric_limits<double>::quiet_NaN()};
      for (int l = 0; l < DL; ++l) {
        switch (rng_() % 5) {
          case 4:
            in[l] = overflow[rng_() % std::size(overflow)];
            break;
          case 0:  // a float plus half its last place: a tie
            in[l] = static_cast<double>(static_cast<float>(rng_() % 100000) * 0.37f) +
                    std::ldexp(1.0, -30);
            break;
          case 1:  // near float's smallest normal
            in[l] = std::ldexp(static_cast<double>(rng_() % 1000000), -150);
            break;
          case 2:  // past float's range
            in[l] = std::ldexp(1.0 + static_cast<double>(rng_() % 1000) / 1000.0, 128);
            break;
          default:
            in[l] = std::bit_cast<double>(rng_() & 0xbfffffffffffffffull);  // |x| < 2
        }
      }
      p.to_float(in, out);
      for (int l = 0; l < DL; ++l) {
        const double want = static_cast<double>(static_cast<float>(in[l]));
        if (std::isnan(want)) {
          ASSERT_TRUE(std::isnan(out[l])) << mosaic::to_string(p.isa);
          continue;
        }
        ASSERT_EQ(std::bit_cast<std::uint64_t>(out[l]), std::bit_cast<std::uint64_t>(want))
            << mosaic::to_string(p.isa) << " in=" << in[l];
      }
    }
  }
}

// The lanes of b packed into the low lanes, in lane order, for every b.
// widen() reads exactly the double lanes' count of floats and converts them exactly; narrow()
// rounds each double lane as static_cast<float> does (ties to even, overflow to infinity, NaN
// to NaN) and writes exactly that many floats.
TEST_F(SimdMask, WidenAndNarrowConvertLikeScalarCasts) {
  constexpr float kGuard = -12345.5f;
  for (const Probe& p : probes_) {
    const int DL = p.double_lanes();
    for (int round = 0; round < 2000; ++round) {
      float in[kMaxLanes + 1];
      double din[kMaxLanes];
      for (int l = 0; l < DL; ++l) {
        in[l] = std::bit_cast<float>(static_cast<std::uint32_t>(rng_()));
        const float f = static_cast<float>(rng_() % 100000) * 0.37f;
        switch (rng_() % 4) {
          case 0:  // a float plus half its last place: a tie
            din[l] = static_cast<double>(f) + std::ldexp(1.0, -30);
            break;
          case 1:  // past float's range
            din[l] = -std::ldexp(1.0 + static_cast<double>(rng_() % 1000) / 1000.0, 128);
            break;
          case 2:  // below float's smallest normal
            din[l] = std::ldexp(static_cast<double>(rng_() % 1000000), -150);
            break;
          default:
            din[l] = std::bit_cast<double>(rng_());
        }
      }
      double wide[kMaxLanes];
      p.widen(in, wide);
      float out[kMaxLanes + 1];
      std::fill(std::begin(out), std::end(out), kGuard);
      p.narrow(din, out);
      for (int l = 0; l < DL; ++l) {
        const double want_wide = static_cast<double>(in[l]);
        if (std::isnan(want_wide))
          ASSERT_TRUE(std::isnan(wide[l])) << mosaic::to_string(p.isa);
        else
          ASSERT_EQ(std::bit_cast<std::uint64_t>(wide[l]), std::bit_cast<std::uint64_t>(want_wide))
              << mosaic::to_string(p.isa) << " in=" << in[l];
        const float want = static_cast<float>(din[l]);
        if (std::isnan(want))
          ASSERT_TRUE(std::isnan(out[l])) << mosaic::to_string(p.isa);
        else
          ASSERT_EQ(std::bit_cast<std::uint32_t>(out[l]), std::bit_cast<std::uint32_t>(want))
              << mosaic::to_string(p.isa) << " in=" << din[l];
      }
      ASSERT_EQ(out[DL], kGuard) << mosaic::to_string(p.isa) << ": narrow wrote past its lanes";
    }
  }
}

TEST_F(SimdMask, CompressPacksTheMaskedLanesInOrder) {
  for (const Probe& p : probes_) {
    const int L = p.lanes();
    std::int32_t in[kMaxLanes];
    float fin[kMaxLanes];
    for (int l = 0; l < L; ++l) {
      in[l] = 1000 + 17 * l;
      fin[l] = 0.5f + static_cast<float>(l);
    }
    for (std::uint32_t b = 0; b < (1u << L); ++b) {
      std::int32_t out[kMaxLanes];
      float fout[kMaxLanes];
      p.compress_int(in, b, out);
      p.compress_float(fin, b, fout);
      int k = 0;
      for (int l = 0; l < L; ++l) {
        if (!(b >> l & 1u)) continue;
        ASSERT_EQ(out[k], in[l]) << mosaic::to_string(p.isa) << " b=" << b << " lane " << k;
        ASSERT_EQ(fout[k], fin[l]) << mosaic::to_string(p.isa) << " b=" << b << " lane " << k;
        ++k;
      }
    }
  }
}

// Lane l is the box mean of pixel l's S RGBA8 words (S = 4, 8, 16; words l * S .. l * S + S - 1
// of the vectors laid end to end), per byte (sum + S / 2) / S as resolve::box_mean() rounds, for
// any bytes (255s included).
TEST_F(SimdMask, MeansAverageEachPixelsSamplesPerByte) {
  for (const Probe& p : probes_) {
    const int L = p.lanes();
    for (const int S : {4, 8, 16}) {
      for (int round = 0; round < 300; ++round) {
        std::vector<std::int32_t> in(static_cast<std::size_t>(S * L));
        std::int32_t out[kMaxLanes];
        for (int i = 0; i < S * L; ++i)
          in[i] = round == 0 ? static_cast<std::int32_t>(0xffffffffu)
                  : round == 1
                      ? static_cast<std::int32_t>(static_cast<std::uint32_t>(i) * 0x01020304u)
                      : static_cast<std::int32_t>(rng_());
        p.means(S, in.data(), out);
        for (int l = 0; l < L; ++l) {
          std::uint32_t want = 0;
          for (int byte = 0; byte < 4; ++byte) {
            unsigned sum = 0;
            for (int k = 0; k < S; ++k)
              sum += static_cast<std::uint32_t>(in[l * S + k]) >> (8 * byte) & 0xffu;
            want |= ((sum + S / 2) / S) << (8 * byte);
          }
          ASSERT_EQ(static_cast<std::uint32_t>(out[l]), want)
              << mosaic::to_string(p.isa) << " " << S << "x round " << round << " lane " << l;
        }
      }
    }
  }
}

// Lane l is lane idx[l] of the input, for any indices (repeats included).
TEST_F(SimdMask, PermutePicksTheIndexedLane) {
  for (const Probe& p : probes_) {
    const int L = p.lanes();
    for (int round = 0; round < 200; ++round) {
      std::int32_t in[kMaxLanes], idx[kMaxLanes], out[kMaxLanes];
      for (int l = 0; l < L; ++l) {
        in[l] = static_cast<std::int32_t>(rng_());
        idx[l] = round == 0 ? L - 1 - l : static_cast<std::int32_t>(rng_() % L);
      }
      p.permute(in, idx, out);
      for (int l = 0; l < L; ++l)
        ASSERT_EQ(out[l], in[idx[l]])
            << mosaic::to_string(p.isa) << " round " << round << " lane " << l;
    }
  }
}

// Records at scattered addresses (a batch's corners name any vertex) into lanes: every word of
// every record where it belongs, bit for bit, and word 0's two floats widened exactly.
TEST_F(SimdMask, RecordsBecomeColumns) {
  struct alignas(32) Record {
    std::uint64_t word[4];
  };
  std::vector<Record> pool(64);
  for (Record& r : pool)
    for (std::uint64_t& w : r.word) w = rng_();
  for (Record& r : pool) {  // word 0: two finite floats, signed zeros and subnormals among them
    const float f[2] = {std::bit_cast<float>(static_cast<std::uint32_t>(rng_() & 0x807fffffu) |
                                             (static_cast<std::uint32_t>(rng_() % 254) << 23)),
                        rng_() % 4 == 0 ? -0.0f : std::ldexp(1.0f, -140)};
    std::memcpy(&r.word[0], f, sizeof f);
  }
  for (const Probe& p : probes_) {
    const int DL = p.double_lanes();
    for (int k = 0; k < 200; ++k) {
      const void* rows[8];
      int which[8];
      for (int l = 0; l < DL; ++l) rows[l] = &pool[which[l] = static_cast<int>(rng_() % 64)];
      std::uint64_t words[4][16];
      double low[8], high[8];
      p.columns(rows, words, low, high);
      for (int l = 0; l < DL; ++l) {
        const Record& r = pool[which[l]];
        for (int j = 0; j < 4; ++j)
          ASSERT_EQ(words[j][l], r.word[j]) << mosaic::to_string(p.isa) << " word " << j;
        float f[2];
        std::memcpy(f, &r.word[0], sizeof f);
        ASSERT_EQ(std::bit_cast<std::uint64_t>(low[l]),
                  std::bit_cast<std::uint64_t>(static_cast<double>(f[0])))
            << mosaic::to_string(p.isa);
        ASSERT_EQ(std::bit_cast<std::uint64_t>(high[l]),
                  std::bit_cast<std::uint64_t>(static_cast<double>(f[1])))
            << mosaic::to_string(p.isa);
      }
    }
  }
}

// The first 16 bytes of records at scattered addresses (a window's corners name any vertex), one
// record per float lane: each 32-bit word where it belongs, its bits as they are.
TEST_F(SimdMask, RecordHeadsBecomeFloatLanes) {
  struct alignas(32) Record {
    std::uint32_t word[8];
  };
  std::vector<Record> pool(64);
  for (Record& r : pool)
    for (std::uint32_t& w : r.word) w = static_cast<std::uint32_t>(rng_());
  for (const Probe& p : probes_) {
    const int L = p.lanes();
    for (int k = 0; k < 200; ++k) {
      const void* rows[kMaxLanes];
      int which[kMaxLanes];
      for (int l = 0; l < L; ++l) rows[l] = &pool[which[l] = static_cast<int>(rng_() % 64)];
      std::uint32_t words[4][16];
      p.heads(rows, words);
      for (int l = 0; l < L; ++l)
        for (int j = 0; j < 4; ++j)
          ASSERT_EQ(words[j][l], pool[which[l]].word[j])
              << mosaic::to_string(p.isa) << " lane " << l << " word " << j;
    }
  }
}

// Lanes into records: integers (negative, and up to 2^50) as int64 words, pairs of floats and of
// int32s packed low then high, and raw words, each record's words where they belong.
TEST_F(SimdMask, LanesBecomeRecords) {
  for (const Probe& p : probes_) {
    const int DL = p.double_lanes();
    for (int k = 0; k < 500; ++k) {
      double ints[8], a[8], b[8], c[8], d[8];
      std::uint64_t more[8][16] = {};
      for (int l = 0; l < DL; ++l) {
        const auto mag = static_cast<double>(rng_() >> (14 + rng_() % 50));  // below 2^50
        ints[l] = rng_() % 2 ? -mag : mag;
        a[l] =
            std::ldexp(static_cast<double>(rng_() % 2000000) - 1e6, -static_cast<int>(rng_() % 20));
        b[l] = rng_() % 5 == 0 ? -0.0 : static_cast<double>(rng_() % 1000) / 7.0;
        c[l] = static_cast<double>(static_cast<std::int32_t>(rng_()));
        d[l] = static_cast<double>(static_cast<std::int32_t>(rng_() % 70000) - 35000);
        for (int j = 3; j < 8; ++j) more[j][l] = rng_();
      }
      alignas(64) std::uint64_t out[8][8];
      p.rows(ints, a, b, c, d, more, out);
      for (int l = 0; l < DL; ++l) {
        ASSERT_EQ(static_cast<std::int64_t>(out[l][0]), static_cast<std::int64_t>(ints[l]))
            << mosaic::to_string(p.isa) << " lane " << l;
        const float fa = static_cast<float>(a[l]), fb = static_cast<float>(b[l]);
        const auto ia = static_cast<std::int32_t>(c[l]), ib = static_cast<std::int32_t>(d[l]);
        ASSERT_EQ(out[l][1], std::uint64_t{std::bit_cast<std::uint32_t>(fa)} |
                                 std::uint64_t{std::bit_cast<std::uint32_t>(fb)} << 32)
            << mosaic::to_string(p.isa) << " lane " << l;
        ASSERT_EQ(out[l][2], std::uint64_t{static_cast<std::uint32_t>(ia)} |
                                 std::uint64_t{static_cast<std::uint32_t>(ib)} << 32)
            << mosaic::to_string(p.isa) << " lane " << l;
        for (int j = 3; j < 8; ++j)
          ASSERT_EQ(out[l][j], more[j][l]) << mosaic::to_string(p.isa) << " word " << j;
      }
    }
  }
}

}  // namespace
