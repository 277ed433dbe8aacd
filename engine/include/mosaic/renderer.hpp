// mosaic/renderer.hpp — renders a frame (a list of draws) into a RenderTarget.
//
// Takes: a Frame and a RenderTarget. Gives: the resolved image in the target and FrameStats.
// The fast path is the default; Isa::kReference selects the exact scalar oracle, which every
// fast path matches bit for bit.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "mosaic/draw.hpp"
#include "mosaic/occlusion.hpp"
#include "mosaic/render_target.hpp"
#include "mosaic/types.hpp"

namespace mosaic {

/// A frame: draws in submission order, and how they are shaded and ordered.
struct Frame {
  /// The draws. Every sample sees their triangles in this order (draw by draw, triangle by
  /// triangle), whatever the thread count. Only viewed: the buffers must outlive render().
  std::span<const Draw> draws;
  /// SSAA: colour is evaluated at every sample instead of once per pixel (MSAA).
  bool ssaa = false;
  /// Painter's algorithm: every draw's depth test is turned off and its triangles are drawn
  /// back to front, sorted (stably) by the mean depth of their vertices. It exists to show what
  /// the z-buffer fixes: interpenetrating and cyclic triangles come out wrong.
  bool painter = false;
  /// Keep the frame's hierarchical z (exact depth bounds of every 8×8-pixel block) for
  /// occlusion queries, in Renderer::hierarchical_z(). Costs one pass over each tile's depth
  /// while it is in cache; without it, no block bounds are written.
  bool keep_hierarchical_z = false;
  /// Where each sample's colour and depth start: the target's clear values, or what its
  /// previous frame left, so that a second pass draws over the first (the result is the one
  /// frame of both passes' draws, bit for bit). Loading reads the target's kept samples: it
  /// needs TargetOptions::keep_sample_color for colour and keep_sample_depth for depth, or
  /// render() throws Error{kInvalidArgument}. A target not rendered yet holds its clear values.
  LoadOp color_load = LoadOp::kClear;
  LoadOp depth_load = LoadOp::kClear;
  /// Occluders nearest first: each tile draws the triangles of consecutive occluder draws
  /// (color_write off, depth_write on, a depth test of less / less-equal, or of greater /
  /// greater-equal) in order of their nearest depth instead of submission order, so that
  /// hierarchical z rejects the farther ones. Every sample still keeps the nearest of its depths,
  /// so depth, image and hierarchical z are bit for bit those of submission order; the counters
  /// of tested and written samples and of hierarchical-z blocks count the order drawn.
  bool occluders_nearest_first = false;
};

/// One screen tile's share of a frame (FrameStats::tile_costs).
struct TileCost {
  int x0 = 0, y0 = 0, width = 0, height = 0;  ///< the tile's pixels
  std::uint32_t triangles = 0;                ///< triangles binned to it
  double ms = 0;                              ///< its worker's time: clear, rasterize, resolve
};

/// One front-end chunk's share of a frame (FrameStats::chunk_costs).
struct ChunkCost {
  std::uint32_t triangles = 0;  ///< triangles submitted in the chunk
  double ms_setup = 0;          ///< transform, clip, cull, snap and set up
  double ms_binning = 0;        ///< binning the chunk's triangles into its tile table
};

/// Bytes of the fast path's per-frame memory that a frame filled, by what holds them; the
/// Renderer keeps at least this much between frames. All 0 for Isa::kReference, which keeps none.
struct FrameMemory {
  std::uint64_t vertices = 0;  ///< the vertex stage's records (32 bytes a vertex)
  std::uint64_t setups = 0;    ///< the front end's TriangleSetups (128 bytes a triangle set up)
  std::uint64_t planes = 0;    ///< out-of-line planes: interpolated colours and varyings
  /// the tile bins: per chunk, each tile's offset and each (triangle, tile) pair's index, and the
  /// pairs the binner sorted them from
  std::uint64_t bins = 0;
  std::uint64_t total() const { return vertices + setups + planes + bins; }
};

/// Per-frame counters and timings. Counters are exact and do not depend on the thread count.
struct FrameStats {
  std::uint64_t triangles_in = 0;           ///< triangles submitted
  std::uint64_t triangles_nonfinite = 0;    ///< culled: NaN or Inf coordinate
  std::uint64_t triangles_culled_face = 0;  ///< culled: back or front face
  std::uint64_t triangles_degenerate = 0;   ///< culled: zero area after snapping
  std::uint64_t triangles_outside = 0;      ///< culled: outside the viewport or depth range
  std::uint64_t triangles_clipped = 0;      ///< submitted triangles that needed clipping
  /// culled: covers no sample, exactly (its box holds no sample position, or its few candidate
  /// samples are all outside it); not counted in triangles_drawn
  std::uint64_t triangles_no_sample = 0;
  std::uint64_t triangles_drawn = 0;      ///< triangles rasterized, after clipping and culling
  std::uint64_t triangles_binned = 0;     ///< (triangle, tile) pairs in the bins
  std::uint64_t blocks_hiz_rejected = 0;  ///< blocks skipped by hierarchical z
  std::uint64_t blocks_hiz_accepted = 0;  ///< blocks where hierarchical z skipped the depth test
  std::uint64_t samples_tested = 0;       ///< covered samples that reached the depth test
  /// Samples that passed the depth test, over all triangles: their colour was written, unless
  /// the draw's DrawState::color_write was off (and their depth, if depth_write was on).
  std::uint64_t samples_written = 0;
  FrameMemory memory;  ///< exact, and independent of the thread count, as the counters are
  /// Wall-clock milliseconds of each stage and of the whole frame. ms_resolve alone is summed
  /// over the workers (the resolve runs inside each tile's task), so it is thread time. Each
  /// front-end chunk is binned as soon as it is set up, in the same task, so ms_setup and
  /// ms_binning share that stage's wall time in proportion to the thread time the chunks spent
  /// in each (ms_setup also holds validation, before the stage).
  double ms_setup = 0, ms_binning = 0, ms_raster = 0, ms_resolve = 0, ms_total = 0;
  int tile_size = 0;  ///< tile edge in pixels the fast path used (0 for the reference)
  /// Per-tile and per-chunk costs, in tile and chunk order; filled only when
  /// RendererOptions::record_costs is set (the scaling model of `mosaic-scaling` reads them).
  std::vector<TileCost> tile_costs;
  std::vector<ChunkCost> chunk_costs;
  Isa isa = Isa::kReference;  ///< the path that rendered the frame
  int threads = 1;            ///< worker threads used
};

/// Renderer configuration.
struct RendererOptions {
  /// Worker threads, 0 to kMaxThreads; 0 means every hardware thread. More threads than cores is
  /// allowed (the image never depends on the count); while such a Renderer lives it raises oneTBB's
  /// process-wide worker limit to its count, and two such Renderers share the smaller of the two.
  int threads = 0;
  Isa isa = Isa::kAuto;  ///< kAuto picks the best SIMD path the CPU runs
  /// Time every tile and front-end chunk into FrameStats::tile_costs / chunk_costs. Costs two
  /// clock reads per tile (chunks are timed anyway, for ms_setup and ms_binning); off by default.
  bool record_costs = false;
  /// Screen tile edge of the fast path in pixels: a power of two from kMinTileSize to
  /// kMaxTileSize, or 0 to let the renderer choose: by the target's sample count (128 px up to 4
  /// samples, 64 px beyond), and 32 px for a frame whose triangles reach fewer than 16 of those
  /// (README, "Scaling past two cores"). Only speed depends on it, never the image.
  int tile_size = 0;
};

/// Tile edges RendererOptions::tile_size accepts: powers of two (binning divides by shifting)
/// from the 8×8-pixel block the tile kernels work in up to the largest tile a worker's scratch
/// memory holds (128² px × 16 samples × (4 B colour + 4 B depth) = 2 MiB per worker thread).
inline constexpr int kMinTileSize = 8;
inline constexpr int kMaxTileSize = 128;

/// The tile edge the renderer picks when RendererOptions::tile_size is 0, for a target with
/// `samples` samples per pixel (1, 4, 8 or 16).
int default_tile_size(int samples);

/// The instruction sets this build and this CPU can run, best last (kReference always first).
std::vector<Isa> available_isas();

/// Upper bound of RendererOptions::threads: far past any machine, low enough to catch garbage.
inline constexpr int kMaxThreads = 1024;

/// The largest frame a Renderer is to render, for Renderer::reserve().
struct FrameReserve {
  int width = 1, height = 1, samples = 1;  ///< the target's size and sample count
  std::uint64_t triangles = 0;             ///< triangles submitted by the frame's draws
  /// Vertices of the frame's indexed draws, which the vertex stage projects once each (at 32
  /// bytes a vertex); at most 2^32 - 1.
  std::uint64_t vertices = 0;
};

/// Renders frames. Holds worker threads and per-frame memory, so keep one alive across frames.
///
/// Threads. One render() at a time per Renderer: a render() that starts while another runs (from
/// a second thread, or from a shader of the frame) throws Error{kBusy} at once and leaves both
/// the running frame and its own target untouched. Separate Renderers may render from separate
/// threads at the same time, each into its own RenderTarget: the pattern for an engine that
/// renders two views at once is one Renderer per thread. Each has its own oneTBB arena, and
/// oneTBB shares one pool of worker threads among all arenas of the process, so two Renderers
/// of 2 threads on 2 cores do not run 4 busy threads. While a Renderer does not render, its
/// const members (and the HierarchicalZ it returns) may be read from any thread, by many at
/// once. The draws' buffers are only read: two renders may share them.
class Renderer {
 public:
  /// Throws Error{kUnsupportedIsa} if options.isa cannot run here, and Error{kInvalidArgument}
  /// for a thread count outside 0..kMaxThreads or a tile size RendererOptions does not allow.
  explicit Renderer(RendererOptions options = {});
  /// Releases the worker arena and per-frame memory (and oneTBB's raised worker cap, if any).
  ~Renderer();
  /// Moves the workers and memory; the moved-from Renderer may only be destroyed, assigned
  /// to, or queried: its render() throws Error{kInvalidArgument}, isa() answers kReference,
  /// threads() 0, and hierarchical_z() is empty.
  Renderer(Renderer&&) noexcept;
  /// As the move constructor.
  Renderer& operator=(Renderer&&) noexcept;

  /// Sizes and touches the memory of a frame as large as `frame` (the per-chunk setups and
  /// bins, the tile tables, the projected vertices), and starts the worker threads, so that the
  /// first frame of that size costs what the later ones do. A larger frame still grows the
  /// memory as it needs; a Renderer never shrinks it. Throws Error{kInvalidArgument} for a size
  /// outside 1..kMaxTargetSize, a sample count other than 1, 4, 8 or 16, or counts past their
  /// bounds; does nothing for Isa::kReference, which keeps no memory between frames.
  void reserve(const FrameReserve& frame);

  /// Renders one frame: clear, draws, resolve. Validates every draw first and throws
  /// Error{kIndexOutOfRange} or Error{kInvalidDraw} without touching the target; throws
  /// Error{kBusy} if this Renderer is already rendering.
  FrameStats render(const Frame& frame, RenderTarget& target);

  /// The hierarchical z of the last frame rendered with Frame::keep_hierarchical_z; empty if the
  /// last frame did not keep one (its queries then answer "visible"). Valid until the next
  /// render().
  const HierarchicalZ& hierarchical_z() const noexcept;

  /// The path render() uses (never kAuto).
  Isa isa() const noexcept;
  /// Worker threads render() uses: RendererOptions::threads, or the hardware thread count for
  /// 0; always 1 for Isa::kReference, which is single-threaded.
  int threads() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Checks a frame against a target without rendering; throws as render() would.
void validate(const Frame& frame, const RenderTarget& target);

}  // namespace mosaic
