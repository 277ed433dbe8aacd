// Render targets over memory the caller owns (ColorView, DepthView), on the reference and every
// SIMD path, at 1, 4 and 16 samples: the image in RGBA8 or BGRA8 with a row stride, and the
// sample depth with a row stride, equal to what a target that owns its memory gets, and not one
// byte written outside the rectangle (guard bytes around it and in every row's padding). A
// depth view is also what a frame loads from; a PNG written from a view target is the owned
// target's file. Views that cannot hold the target are errors.
//
// What breaks it: a resolve that writes rows at width instead of the stride, a tile at the image's
// right edge that writes a whole tile's row, a BGRA swizzle on one path only, a depth-only frame
// that fills the owned buffer instead of the caller's, or sample depth written unstrided.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "reference_test_util.hpp"

namespace mosaic {
namespace {

constexpr int kW = 77, kH = 53;
constexpr std::uint8_t kGuard = 0xa5;
/// Guard rows above and below the rectangle, and padding bytes after each row (not a multiple
/// of 4: the colour rows are not even word-aligned).
constexpr std::size_t kGuardRows = 3, kColorPad = 13, kDepthPadFloats = 5;

// Caller memory with the rectangle `rows` × `row_bytes` inside guard bytes.
struct Guarded {
  std::vector<std::uint8_t> bytes;
  std::size_t stride = 0, rows = 0, row_bytes = 0;
  Guarded(std::size_t rows_, std::size_t row_bytes_, std::size_t pad)
      : stride(row_bytes_ + pad), rows(rows_), row_bytes(row_bytes_) {
    bytes.assign(stride * (rows + 2 * kGuardRows), kGuard);
  }
  std::uint8_t* first() { return bytes.data() + kGuardRows * stride; }
  // Bytes outside the rectangle that no longer hold the guard.
  std::size_t touched_outside() const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      const std::size_t row = i / stride, col = i % stride;
      const bool inside = row >= kGuardRows && row < kGuardRows + rows && col < row_bytes;
      n += !inside && bytes[i] != kGuard ? 1 : 0;
    }
    return n;
  }
};

TEST(TargetViews, ColourViewsGetTheOwnedImageAndNothingOutside) {
  test::Rng rng(7070);
  const std::vector<Mesh> meshes = test::random_draws(kW, kH, 3, 40, rng);
  std::vector<Mesh> depth_only = meshes;
  for (Mesh& m : depth_only) m.state.color_write = false;
  for (int samples : {1, 4, 16})
    for (PixelFormat format : {PixelFormat::kRgba8, PixelFormat::kBgra8})
      for (Isa isa : available_isas()) {
        const std::string what = std::string(to_string(isa)) + " " + std::to_string(samples) +
                                 (format == PixelFormat::kBgra8 ? "x bgra" : "x rgba");
        Renderer r(RendererOptions{2, isa});
        RenderTarget owned(kW, kH, samples);
        owned.set_clear(test::kClear);
        Guarded mem(kH, 4 * kW, kColorPad);
        RenderTarget view(kW, kH, samples, ColorView{mem.first(), mem.stride, format});
        view.set_clear(test::kClear);
        EXPECT_TRUE(view.over_caller_memory());
        EXPECT_TRUE(view.color().empty());
        // A depth-only frame (the image is filled with the clear colour), then a colour one.
        for (const std::vector<Mesh>* pass : {&std::as_const(depth_only), &meshes}) {
          const std::vector<Draw> draws = test::draws_of(*pass);
          Frame f;
          f.draws = draws;
          r.render(f, owned);
          r.render(f, view);
          std::size_t wrong = 0;
          for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
              const Rgba8 want = owned.pixel(x, y);
              const std::uint8_t* px = mem.first() + std::size_t(y) * mem.stride + 4u * x;
              const bool bgra = format == PixelFormat::kBgra8;
              const Rgba8 raw{px[bgra ? 2 : 0], px[1], px[bgra ? 0 : 2], px[3]};
              wrong += raw == want && view.pixel(x, y) == want ? 0 : 1;
            }
          EXPECT_EQ(wrong, 0u) << what;
          EXPECT_EQ(mem.touched_outside(), 0u) << what;
          EXPECT_EQ(view.image_hash(), owned.image_hash()) << what;
        }
      }
}

TEST(TargetViews, DepthViewsHoldTheSampleDepthAndAreLoadedFrom) {
  test::Rng rng(7071);
  const std::vector<Mesh> meshes = test::random_draws(kW, kH, 4, 40, rng);
  const std::vector<Mesh> first(meshes.begin(), meshes.begin() + 2),
      second(meshes.begin() + 2, meshes.end());
  for (int samples : {1, 4, 16})
    for (Isa isa : available_isas()) {
      const std::string what = std::string(to_string(isa)) + " " + std::to_string(samples) + "x";
      Renderer r(RendererOptions{2, isa});
      RenderTarget owned(kW, kH, samples, TargetOptions{true, false});
      const std::vector<Draw> all = test::draws_of(meshes);
      Frame whole;
      whole.draws = all;
      r.render(whole, owned);

      const std::size_t row = std::size_t(kW) * samples * sizeof(float);
      Guarded color(kH, 4 * kW, kColorPad), depth(kH, row, kDepthPadFloats * sizeof(float));
      // Sample colour kept as well, so that the second pass loads both and the image is whole.
      RenderTarget view(kW, kH, samples, ColorView{color.first(), color.stride},
                        DepthView{reinterpret_cast<float*>(depth.first()), depth.stride},
                        TargetOptions{false, true});
      EXPECT_TRUE(view.sample_depth().empty());
      const std::vector<Draw> a = test::draws_of(first), b = test::draws_of(second);
      Frame pass;
      pass.draws = a;
      r.render(pass, view);
      pass.draws = b;
      pass.depth_load = LoadOp::kLoad;
      pass.color_load = LoadOp::kLoad;
      r.render(pass, view);
      std::size_t wrong = 0;
      for (int y = 0; y < kH; ++y) {
        const std::uint8_t* got = depth.first() + std::size_t(y) * depth.stride;
        const float* want = owned.sample_depth().data() + std::size_t(y) * kW * samples;
        wrong += std::memcmp(got, want, row) == 0 ? 0 : 1;
      }
      EXPECT_EQ(wrong, 0u) << what << ": rows of sample depth differ";
      EXPECT_EQ(depth.touched_outside(), 0u) << what;
      EXPECT_EQ(color.touched_outside(), 0u) << what;
      EXPECT_EQ(view.image_hash(), owned.image_hash()) << what;
    }
}

TEST(TargetViews, APngOfAViewTargetIsTheOwnedTargetsFile) {
  test::Rng rng(7072);
  const std::vector<Mesh> meshes = test::random_draws(kW, kH, 2, 30, rng);
  const std::vector<Draw> draws = test::draws_of(meshes);
  Frame f;
  f.draws = draws;
  Renderer r;
  RenderTarget owned(kW, kH, 4);
  Guarded mem(kH, 4 * kW, kColorPad);
  RenderTarget view(kW, kH, 4, ColorView{mem.first(), mem.stride, PixelFormat::kBgra8});
  r.render(f, owned);
  r.render(f, view);
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  const std::filesystem::path a = dir / "mosaic_views_owned.png", b = dir / "mosaic_views_view.png";
  write_image(owned, a);
  write_image(view, b);
  auto bytes = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_FALSE(bytes(a).empty());
  EXPECT_TRUE(bytes(a) == bytes(b));
  std::filesystem::remove(a);
  std::filesystem::remove(b);
}

TEST(TargetViews, ViewsThatCannotHoldTheTargetAreErrors) {
  std::vector<std::uint8_t> mem(4 * kW * kH);
  std::vector<float> depth(std::size_t(kW) * kH * 4 + 1);
  auto rejects = [](auto make, const std::string& says) {
    try {
      make();
      ADD_FAILURE() << says << ": accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), Errc::kInvalidArgument) << says;
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  rejects([&] { RenderTarget t(kW, kH, 1, ColorView{nullptr, 4 * kW}); }, "null");
  rejects([&] { RenderTarget t(kW, kH, 1, ColorView{mem.data(), 4 * kW - 1}); }, "shorter");
  rejects(
      [&] {
        RenderTarget t(kW, kH, 1, ColorView{mem.data(), 4 * kW, PixelFormat(7)});
      },
      "format");
  rejects(
      [&] {
        RenderTarget t(kW, kH, 4, ColorView{mem.data(), 4 * kW},
                       DepthView{depth.data(), 4 * kW * sizeof(float) - 4});
      },
      "shorter");
  rejects(
      [&] {
        RenderTarget t(kW, kH, 1, ColorView{mem.data(), 4 * kW},
                       DepthView{depth.data(), kW * sizeof(float) + 2});
      },
      "multiples of 4");
  // The sizes and sample counts are checked as for any target.
  EXPECT_THROW(RenderTarget(0, kH, 1, ColorView{mem.data(), 4 * kW}), Error);
  EXPECT_THROW(RenderTarget(kW, kH, 3, ColorView{mem.data(), 4 * kW}), Error);
  // A valid view target loads from its depth view: no kept-sample error.
  RenderTarget ok(kW, kH, 1, ColorView{mem.data(), 4 * kW},
                  DepthView{depth.data(), kW * sizeof(float)});
  Frame f;
  f.depth_load = LoadOp::kLoad;
  EXPECT_NO_THROW(Renderer().render(f, ok));
}

}  // namespace
}  // namespace mosaic
