// The tile kernels' sample layout (raster/tile.hpp): a block's samples pixel-major, sample s of
// pixel p at word p * S + s, and the masks over them in the same order. The helpers that move
// between pixel masks and sample masks are checked against the definition, bit by bit, for
// every sample count, on empty, full, sparse and random masks.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "raster/tile.hpp"

namespace {

using mosaic::raster::kBlockPixels;

constexpr int kSampleCounts[] = {1, 2, 4, 8, 16};

bool sample_bit(const std::uint64_t* words, int S, int p, int s) {
  const int g = p * S + s;
  return (words[g / 64] >> (g % 64)) & 1u;
}

// Masks with every density: none, all, one bit, and random ones sparse and dense.
std::vector<std::vector<std::uint64_t>> masks(int S, std::mt19937_64& rng) {
  std::vector<std::vector<std::uint64_t>> out;
  out.emplace_back(S, 0);
  out.emplace_back(S, ~std::uint64_t{0});
  for (int g = 0; g < 64 * S; g += 7) {
    std::vector<std::uint64_t> one(S, 0);
    one[g / 64] = std::uint64_t{1} << (g % 64);
    out.push_back(one);
  }
  for (int k = 0; k < 300; ++k) {
    std::vector<std::uint64_t> w(S);
    for (std::uint64_t& x : w)
      x = k % 3 == 0 ? rng() & rng() & rng() : k % 3 == 1 ? rng() : rng() | rng();
    out.push_back(w);
  }
  return out;
}

TEST(TileLayout, PixelsOfSetsAPixelWhereAnyOfItsSamplesIs) {
  std::mt19937_64 rng(1);
  for (const int S : kSampleCounts)
    for (const std::vector<std::uint64_t>& w : masks(S, rng)) {
      std::uint64_t want = 0;
      for (int p = 0; p < kBlockPixels; ++p)
        for (int s = 0; s < S; ++s)
          if (sample_bit(w.data(), S, p, s)) want |= std::uint64_t{1} << p;
      ASSERT_EQ(mosaic::raster::pixels_of(w.data(), S), want) << S << " samples";
    }
}

TEST(TileLayout, SamplePixelsPicksOneSampleOfEachPixel) {
  std::mt19937_64 rng(2);
  for (const int S : kSampleCounts)
    for (const std::vector<std::uint64_t>& w : masks(S, rng))
      for (int s = 0; s < S; ++s) {
        std::uint64_t want = 0;
        for (int p = 0; p < kBlockPixels; ++p)
          if (sample_bit(w.data(), S, p, s)) want |= std::uint64_t{1} << p;
        ASSERT_EQ(mosaic::raster::sample_pixels(w.data(), S, s), want)
            << S << " samples, sample " << s;
      }
}

TEST(TileLayout, SpreadPixelsSetsEverySampleOfEachPixel) {
  std::mt19937_64 rng(3);
  for (const int S : kSampleCounts)
    for (int k = 0; k < 500; ++k) {
      const std::uint64_t pixels = k == 0 ? 0 : k == 1 ? ~std::uint64_t{0} : rng() & rng();
      std::uint64_t words[mosaic::raster::kMaxSamples];
      mosaic::raster::spread_pixels(pixels, S, words);
      for (int p = 0; p < kBlockPixels; ++p)
        for (int s = 0; s < S; ++s)
          ASSERT_EQ(sample_bit(words, S, p, s), ((pixels >> p) & 1u) != 0)
              << S << " samples, pixel " << p << " sample " << s;
      // And back: the pixels of a spread mask are the mask.
      ASSERT_EQ(mosaic::raster::pixels_of(words, S), pixels) << S << " samples";
    }
}

}  // namespace
