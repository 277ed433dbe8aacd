// frame.cpp — the frame orchestrator: the only place that knows the order of the stages.
//
// validate → vertex stage (each vertex of an indexed mesh projected once) → front end (index
// range, transform, clip, cull, snap, setup) → binning (each chunk right after its front end) →
// tile rasterization (coverage, hierarchical z, depth, shading) → resolve.
// Isa::kReference sends the whole frame to the exact scalar oracle instead.
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <tuple>

#include "bin/binner.hpp"
#include "frame_checks.hpp"
#include "front/front_end.hpp"
#include "isa_dispatch.hpp"
#include "mosaic/errors.hpp"
#include "mosaic/renderer.hpp"
#include "parallel/stage_edges.hpp"
#include "raster/hiz.hpp"
#include "raster/sample_patterns.hpp"
#include "raster/tile.hpp"
#include "reference/reference.hpp"

namespace mosaic {

namespace detail {

namespace {

// The attribute, varying and shader checks of validate_draw().
void validate_shading(const Draw& draw, std::size_t vertices, const std::string& where) {
  if (draw.attribute_stride != 0 && draw.attribute_stride < draw.attribute_count)
    throw Error(Errc::kInvalidDraw, where + "attribute stride " +
                                        std::to_string(draw.attribute_stride) +
                                        " floats is less than the " +
                                        std::to_string(draw.attribute_count) + " attributes");
  const std::size_t row = attribute_row(draw), count = draw.attribute_count;
  // (vertices - 1) * row + count > size, without overflowing.
  if (count > 0 && vertices > 0 &&
      (draw.attributes.size() < count || (draw.attributes.size() - count) / row < vertices - 1))
    throw Error(Errc::kInvalidDraw,
                where + "attribute buffer too short: " + std::to_string(draw.attributes.size()) +
                    " floats for " + std::to_string(vertices) + " vertices of " +
                    std::to_string(count) + " attributes, " + std::to_string(row) +
                    " floats apart");
  if (draw.varyings.empty()) {
    if (draw.shader && draw.shader.varyings_read() > 0)
      throw Error(Errc::kInvalidDraw, where + "the shader reads " +
                                          std::to_string(draw.shader.varyings_read()) +
                                          " varyings and the draw gives none");
    return;
  }
  if (!draw.shader)
    throw Error(Errc::kInvalidDraw, where + "varyings are given but the draw has no shader");
  if (draw.varyings.size() > static_cast<std::size_t>(kMaxVaryings))
    throw Error(Errc::kInvalidDraw, where + std::to_string(draw.varyings.size()) +
                                        " varyings, more than kMaxVaryings (" +
                                        std::to_string(kMaxVaryings) + ")");
  if (draw.varyings.size() < static_cast<std::size_t>(std::max(0, draw.shader.varyings_read())))
    throw Error(Errc::kInvalidDraw,
                where + "the shader reads " + std::to_string(draw.shader.varyings_read()) +
                    " varyings and the draw gives " + std::to_string(draw.varyings.size()));
  for (std::size_t k = 0; k < draw.varyings.size(); ++k)
    if (draw.varyings[k] >= draw.attribute_count)
      throw Error(Errc::kInvalidDraw, where + "varying " + std::to_string(k) + " is attribute " +
                                          std::to_string(draw.varyings[k]) + ", past the " +
                                          std::to_string(draw.attribute_count) +
                                          " attributes per vertex");
}

// The viewport and scissor checks of validate_draw(): whole pixels within ±kMaxTargetSize, which
// keeps every moved coordinate inside the 16.8 format (front/draw_area.hpp); a viewport is at
// least a pixel wide and tall, a scissor may be empty.
void validate_rect(const std::optional<PixelRect>& rect, const char* name, int min_size,
                   const std::string& where) {
  if (!rect) return;
  const PixelRect& r = *rect;
  const auto within = [](int v, int lo) { return v >= lo && v <= kMaxTargetSize; };
  if (within(r.x, -kMaxTargetSize) && within(r.y, -kMaxTargetSize) && within(r.width, min_size) &&
      within(r.height, min_size))
    return;
  throw Error(Errc::kInvalidDraw,
              where + name + " (" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " +
                  std::to_string(r.width) + " x " + std::to_string(r.height) +
                  "): x and y must lie within ±16384, width and height within " +
                  std::to_string(min_size) + "..16384");
}

}  // namespace

void validate_draw(const Draw& draw, std::size_t d, IndexCheck check) {
  const std::string where = "draw " + std::to_string(d) + ": ";
  const bool xyz = !draw.positions_xyz.empty();
  const std::size_t vertices = front::vertex_count(draw);
  if (xyz && !draw.positions.empty())
    throw Error(Errc::kInvalidDraw, where + "give positions or positions_xyz, not both");
  if (draw.positions.stride() < sizeof(glm::vec4) ||
      draw.positions_xyz.stride() < sizeof(glm::vec3))
    throw Error(Errc::kInvalidDraw,
                where + "position stride " +
                    std::to_string(xyz ? draw.positions_xyz.stride() : draw.positions.stride()) +
                    " bytes is less than a position's " +
                    std::to_string(xyz ? sizeof(glm::vec3) : sizeof(glm::vec4)));
  if (vertices > 0xffffffffu) throw Error(Errc::kInvalidDraw, where + "more than 2^32-1 vertices");
  if (!draw.indices.empty()) {
    if (draw.indices.size() % 3 != 0)
      throw Error(Errc::kInvalidDraw, where + "index count " + std::to_string(draw.indices.size()) +
                                          " is not a multiple of 3");
    for (std::size_t i = 0; check == IndexCheck::kHere && i < draw.indices.size(); ++i) {
      if (draw.indices[i] >= vertices)
        throw Error(Errc::kIndexOutOfRange, where + "index " + std::to_string(draw.indices[i]) +
                                                " at position " + std::to_string(i) +
                                                " is out of range (" + std::to_string(vertices) +
                                                " vertices)");
    }
  } else if (vertices % 3 != 0) {
    throw Error(Errc::kInvalidDraw, where + "vertex count " + std::to_string(vertices) +
                                        " is not a multiple of 3 and there is no index buffer");
  }
  validate_shading(draw, vertices, where);
  validate_rect(draw.state.viewport, "viewport", 1, where);
  validate_rect(draw.state.scissor, "scissor", 0, where);
  const std::size_t tris = front::triangle_count(draw);
  if (draw.color_source == ColorSource::kPerTriangle && draw.colors.size() != tris)
    throw Error(Errc::kInvalidDraw, where + std::to_string(draw.colors.size()) + " colours for " +
                                        std::to_string(tris) + " triangles");
  if (draw.color_source == ColorSource::kPerVertex && draw.colors.size() != vertices)
    throw Error(Errc::kInvalidDraw, where + std::to_string(draw.colors.size()) + " colours for " +
                                        std::to_string(vertices) + " vertices");
}

}  // namespace detail

namespace {

void validate(const Frame& frame, const RenderTarget& target, detail::IndexCheck indices) {
  if (frame.color_load == LoadOp::kLoad && !target.options().keep_sample_color)
    throw Error(Errc::kInvalidArgument,
                "Frame::color_load is kLoad, but the target keeps no sample colour to load "
                "(TargetOptions::keep_sample_color)");
  if (frame.depth_load == LoadOp::kLoad && !target.keeps_sample_depth())
    throw Error(Errc::kInvalidArgument,
                "Frame::depth_load is kLoad, but the target keeps no sample depth to load "
                "(TargetOptions::keep_sample_depth, or a DepthView)");
  if (frame.draws.size() > front::kMaxDraws)
    throw Error(Errc::kInvalidArgument, "a frame holds " + std::to_string(frame.draws.size()) +
                                            " draws; at most " + std::to_string(front::kMaxDraws));
  for (std::size_t d = 0; d < frame.draws.size(); ++d)
    detail::validate_draw(frame.draws[d], d, indices);
}

// validate() but the index ranges, which the front end checks (Renderer::Impl::render_fast()).
// A frame that fails is checked whole again, so that it throws validate()'s first error.
void validate_but_indices(const Frame& frame, const RenderTarget& target) {
  try {
    validate(frame, target, detail::IndexCheck::kInFrontEnd);
  } catch (const Error&) {
    validate(frame, target, detail::IndexCheck::kHere);
    throw;
  }
}

}  // namespace

void validate(const Frame& frame, const RenderTarget& target) {
  validate(frame, target, detail::IndexCheck::kHere);
}

int default_tile_size(int samples) { return raster::tile_size_for(samples); }

std::vector<Isa> available_isas() {
  std::vector<Isa> isas{Isa::kReference};
  for (Isa isa : dispatch::runnable_isas()) isas.push_back(isa);
  return isas;
}

namespace {

// A frame that loads samples a target has never rendered loads its clear values (the current
// ones: set_clear() may have changed them since the buffers were made).
void start_loaded_samples(const Frame& frame, RenderTarget& target) {
  if (!target.fresh()) return;
  std::vector<Rgba8>& color = target.sample_color_storage();
  if (frame.color_load == LoadOp::kLoad)
    std::fill(color.begin(), color.end(), target.clear_color());
  // (A DepthView is the caller's: it is loaded as it is.)
  std::vector<float>& depth = target.sample_depth_storage();
  if (frame.depth_load == LoadOp::kLoad)
    std::fill(depth.begin(), depth.end(), target.clear_depth());
}

double ms_between(std::chrono::steady_clock::time_point a,
                  std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

struct Renderer::Impl {
  RendererOptions options;
  Isa isa = Isa::kReference;
  int threads = 1;
  raster::TileKernel kernel = nullptr;
  front::FrontEnd front_end = &front::run_front_end;  ///< the SIMD one of `isa`, when there is one
  front::VertexStage vertex_stage = nullptr;          ///< the SIMD front end's, when there is one
  std::unique_ptr<tbb::global_control> parallelism;   // declared before the arena: outlives it
  std::unique_ptr<tbb::task_arena> arena;
  // Per-frame memory, kept between frames so that steady-state frames do not allocate.
  std::vector<bin::Chunk> chunks;
  front::VertexRecords vertex_records;            // the vertex caches' memory
  std::vector<front::VertexCache> vertex_caches;  // one per draw, empty if it skips the stage
  std::vector<std::pair<std::uint32_t, std::uint32_t>> vertex_blocks;  // (draw, first vertex)
  bin::ChunkPlan plan;
  std::vector<std::uint32_t> draw_triangles;
  std::vector<DrawState> states;
  std::vector<shade::DrawShading> shading;
  bin::TileChunks tile_chunks;
  std::tuple<int, int, int> last_split{0, 0, 0};  // (width, height, samples) of a split last frame
  std::vector<std::pair<std::uint64_t, int>> tile_order;
  // A tile worker's memory: its tile's samples and the bin runs of the tile it works on.
  struct Worker {
    raster::TileScratch scratch;
    std::vector<raster::BinRun> runs;
  };
  // One Worker per arena slot (tbb::this_task_arena::current_thread_index()), made by the
  // constructor and kept across frames. Plain heap memory, not a tbb::enumerable_thread_specific:
  // with that, the fuzzers' per-input leak check (LeakSanitizer) reported the scratch buffers as
  // leaked while the renderer still held them (its elements live in oneTBB's own allocations).
  std::vector<std::unique_ptr<Worker>> workers;
  HierarchicalZ hiz;              // the last frame's, when it asked for it
  std::atomic<bool> busy{false};  // a render() is running: a second one is misuse

  FrameStats render_fast(const Frame& frame, RenderTarget& target);
  std::span<const front::VertexCache> project_vertices(const Frame& frame, int W, int H);
  FrameStats render_reference(const Frame& frame, RenderTarget& target);
  void reserve(const FrameReserve& r);
  std::uint64_t rebin(std::span<bin::Chunk> binned, const bin::TileGrid& grid);
};

namespace {

/// Marks a Renderer busy for the scope of one call; a second call meanwhile is Error{kBusy}.
class BusyGuard {
 public:
  BusyGuard(std::atomic<bool>& busy, const char* call) : busy_(busy) {
    if (busy_.exchange(true, std::memory_order_acquire))
      throw Error(Errc::kBusy, std::string(call) +
                                   " entered while this Renderer renders: one render() at a "
                                   "time, or one Renderer per thread");
  }
  ~BusyGuard() { busy_.store(false, std::memory_order_release); }
  BusyGuard(const BusyGuard&) = delete;
  BusyGuard& operator=(const BusyGuard&) = delete;

 private:
  std::atomic<bool>& busy_;
};

/// The most triangles reserve() sizes a frame for: 2^30, 256 GiB of setups, past any machine.
constexpr std::uint64_t kMaxReservedTriangles = std::uint64_t{1} << 30;

/// The most vertices reserve() sizes a frame for: as many as one draw may index.
constexpr std::uint64_t kMaxReservedVertices = 0xffffffffu;

/// Tiles without triangles drawn by one task of the tile stage.
constexpr std::size_t kEmptyTilesPerTask = 32;

/// Bins a reserved chunk is sized for, per triangle: a small triangle touches one or two tiles.
constexpr std::size_t kReservedTilesPerTriangle = 2;
/// Out-of-line planes a reserved chunk is sized for, per triangle: 1/w and four colours.
constexpr std::size_t kReservedPlanesPerTriangle = 5;

// The bytes of per-frame memory that a frame's vertex caches and chunks hold.
FrameMemory frame_memory(std::span<const front::VertexCache> caches,
                         std::span<const bin::Chunk> chunks) {
  FrameMemory m;
  for (const front::VertexCache& c : caches) m.vertices += c.size * sizeof(front::ProjectedVertex);
  for (const bin::Chunk& c : chunks) {
    m.setups += c.tris.size() * sizeof(front::TriangleSetup);
    m.planes += c.planes.size() * sizeof(front::Plane);
    m.bins += (c.tiles.size() + c.starts.size() + c.indices.size() + c.slot.size()) *
                  sizeof(std::uint32_t) +
              c.pairs.size() * sizeof(std::uint64_t);
  }
  return m;
}

/// Gives `v` room for `n` elements with its pages written (a reserve() alone leaves them to
/// fault in during the first frame), and leaves it empty.
template <class T, class Alloc>
void touch_capacity(std::vector<T, Alloc>& v, std::size_t n) {
  if (v.capacity() < n) {
    v.clear();
    v.resize(n, T{});  // written: a resize() of the plane array leaves its elements unset
  }
  v.clear();
}

}  // namespace

void Renderer::Impl::reserve(const FrameReserve& r) {
  // The automatic choice may bin a frame again on the finer split tiles: sized for those.
  const int tile_size = options.tile_size ? options.tile_size : bin::kSplitTileSize;
  const bin::TileGrid grid(r.width, r.height, tile_size);
  const std::size_t triangles = std::max<std::uint64_t>(r.triangles, 1);
  const std::size_t nchunks = (triangles + bin::kChunkTriangles - 1) / bin::kChunkTriangles;
  if (chunks.size() < nchunks) chunks.resize(nchunks);
  tile_order.reserve(static_cast<std::size_t>(grid.count()));
  if (vertex_stage) vertex_records.reserve_touched(r.vertices);
  parallel::StageEdges edges;
  arena->execute(edges.task([&] {
    tbb::parallel_for(std::size_t{0}, nchunks, edges.task([&](std::size_t i) {
      bin::Chunk& c = chunks[i];
      touch_capacity(c.tris, bin::kChunkTriangles);
      touch_capacity(c.planes, bin::kChunkTriangles * kReservedPlanesPerTriangle);
      if (c.slot.size() < static_cast<std::size_t>(grid.count()))
        c.slot.resize(static_cast<std::size_t>(grid.count()));
      touch_capacity(c.tiles, static_cast<std::size_t>(grid.count()));
      touch_capacity(c.starts, static_cast<std::size_t>(grid.count()) + 1);
      touch_capacity(c.indices, bin::kChunkTriangles * kReservedTilesPerTriangle);
      touch_capacity(c.pairs, bin::kChunkTriangles * kReservedTilesPerTriangle);
    }));
  }));
  edges.join();
}

void Renderer::reserve(const FrameReserve& r) {
  if (!impl_) throw Error(Errc::kInvalidArgument, "reserve() called on a moved-from Renderer");
  if (r.width < 1 || r.width > kMaxTargetSize || r.height < 1 || r.height > kMaxTargetSize)
    throw Error(Errc::kInvalidArgument, "reserve(): size " + std::to_string(r.width) + "x" +
                                            std::to_string(r.height) + " is outside 1..16384");
  if (raster::sample_pattern(r.samples).empty())
    throw Error(Errc::kInvalidArgument,
                "reserve(): sample count " + std::to_string(r.samples) + " is not 1, 4, 8 or 16");
  if (r.triangles > kMaxReservedTriangles)
    throw Error(Errc::kInvalidArgument, "reserve(): " + std::to_string(r.triangles) +
                                            " triangles, more than " +
                                            std::to_string(kMaxReservedTriangles));
  if (r.vertices > kMaxReservedVertices)
    throw Error(Errc::kInvalidArgument, "reserve(): " + std::to_string(r.vertices) +
                                            " vertices, more than " +
                                            std::to_string(kMaxReservedVertices));
  if (impl_->isa == Isa::kReference) return;
  const BusyGuard busy(impl_->busy, "reserve()");
  impl_->reserve(r);
}

Renderer::Renderer(RendererOptions options) : impl_(std::make_unique<Impl>()) {
  if (options.threads < 0 || options.threads > kMaxThreads)
    throw Error(Errc::kInvalidArgument, "thread count " + std::to_string(options.threads) +
                                            " is outside 0.." + std::to_string(kMaxThreads));
  const int ts = options.tile_size;
  if (ts != 0 && (ts < kMinTileSize || ts > kMaxTileSize || !std::has_single_bit(unsigned(ts))))
    throw Error(Errc::kInvalidArgument, "tile size " + std::to_string(ts) +
                                            " is not 0 (automatic) or a power of two from " +
                                            std::to_string(kMinTileSize) + " to " +
                                            std::to_string(kMaxTileSize));
  impl_->options = options;
  const std::vector<Isa> isas = available_isas();
  if (options.isa == Isa::kAuto) {
    impl_->isa = isas.back();
  } else if (std::find(isas.begin(), isas.end(), options.isa) != isas.end()) {
    impl_->isa = options.isa;
  } else {
    throw Error(Errc::kUnsupportedIsa, std::string("instruction set ") + to_string(options.isa) +
                                           " is not available on this CPU or build");
  }
  impl_->threads = options.threads > 0
                       ? options.threads
                       : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (impl_->isa != Isa::kReference) {
    impl_->kernel = dispatch::tile_kernel(impl_->isa);
    if (const front::FrontEnd f = dispatch::front_end(impl_->isa)) {
      impl_->front_end = f;
      impl_->vertex_stage = dispatch::vertex_stage(impl_->isa);
    }
    // oneTBB caps its workers at the core count; asking an arena for more prints a warning and
    // runs on fewer. Oversubscribing is a legitimate request (determinism tests use 7 threads on
    // 2 cores), so raise the cap for as long as this renderer lives.
    if (impl_->threads > tbb::info::default_concurrency())
      impl_->parallelism = std::make_unique<tbb::global_control>(
          tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(impl_->threads));
    impl_->arena = std::make_unique<tbb::task_arena>(impl_->threads);
    // Every worker's tile memory now, its pages written: the options fix how many there are.
    impl_->workers.resize(static_cast<std::size_t>(impl_->threads));
    for (std::unique_ptr<Impl::Worker>& w : impl_->workers) {
      w = std::make_unique<Impl::Worker>();
      std::memset(w->scratch.color.get(), 0, raster::TileScratch::kValues * sizeof(std::uint32_t));
      std::memset(w->scratch.depth.get(), 0, raster::TileScratch::kValues * sizeof(float));
    }
  }
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

// A moved-from Renderer has no Impl. Its accessors answer as documented in renderer.hpp and its
// render() throws, so a use after std::move is a clear error instead of a null dereference.
Isa Renderer::isa() const noexcept { return impl_ ? impl_->isa : Isa::kReference; }
int Renderer::threads() const noexcept {
  if (!impl_) return 0;
  return impl_->isa == Isa::kReference ? 1 : impl_->threads;
}

FrameStats Renderer::render(const Frame& frame, RenderTarget& target) {
  if (!impl_) throw Error(Errc::kInvalidArgument, "render() called on a moved-from Renderer");
  const BusyGuard busy(impl_->busy, "render()");
  const auto t0 = std::chrono::steady_clock::now();
  // The fast path's front end checks each chunk's indices before it reads them, in parallel; the
  // reference and the painter's path (reference::setup_frame()) trust them.
  if (impl_->isa != Isa::kReference && !frame.painter) {
    validate_but_indices(frame, target);
  } else {
    validate(frame, target);
  }
  const double ms_validate = ms_between(t0, std::chrono::steady_clock::now());
  FrameStats stats = impl_->isa == Isa::kReference ? impl_->render_reference(frame, target)
                                                   : impl_->render_fast(frame, target);
  stats.ms_setup += ms_validate;
  stats.ms_total += ms_validate;
  target.mark_rendered();
  return stats;
}

const HierarchicalZ& Renderer::hierarchical_z() const noexcept {
  static const HierarchicalZ kNone;  // what a moved-from Renderer answers: no bounds kept
  return impl_ ? impl_->hiz : kNone;
}

FrameStats Renderer::Impl::render_reference(const Frame& frame, RenderTarget& target) {
  start_loaded_samples(frame, target);
  if (!frame.keep_hierarchical_z) {
    hiz.clear();
    return reference::render(frame, target);
  }
  reference::SampleBuffers samples;
  const FrameStats stats = reference::render(frame, target, &samples);
  hiz.reset(target.width(), target.height());
  raster::block_bounds_from_samples(samples.depth, target.width(), target.height(),
                                    target.samples(), HierarchicalZ::kBlockSize, hiz.zmin_storage(),
                                    hiz.zmax_storage());
  hiz.build_coarse();
  return stats;
}

// The vertex stage, in parallel over blocks of vertices of the draws that want it: one cache per
// draw, empty for the others. The painter's path sets the frame up with the scalar front end,
// which reads no cache.
std::span<const front::VertexCache> Renderer::Impl::project_vertices(const Frame& frame, int W,
                                                                     int H) {
  vertex_caches.assign(frame.draws.size(), {});
  vertex_blocks.clear();
  std::size_t records = 0;
  const auto staged = [&](const Draw& draw) {
    return vertex_stage != nullptr && !frame.painter && front::wants_vertex_stage(draw);
  };
  for (const Draw& draw : frame.draws)
    if (staged(draw)) records += front::vertex_count(draw);
  vertex_records.reserve(records);
  records = 0;
  for (std::size_t d = 0; d < frame.draws.size(); ++d) {
    const Draw& draw = frame.draws[d];
    if (!staged(draw)) continue;
    const std::size_t n = front::vertex_count(draw);
    vertex_caches[d] = {vertex_records.data() + records, n};
    records += n;
    for (std::size_t v = 0; v < n; v += front::kVertexStageBlock)
      vertex_blocks.push_back({static_cast<std::uint32_t>(d), static_cast<std::uint32_t>(v)});
  }
  if (!vertex_blocks.empty()) {
    parallel::StageEdges vertex_edges;
    arena->execute(vertex_edges.task([&] {
      tbb::parallel_for(std::size_t{0}, vertex_blocks.size(), vertex_edges.task([&](std::size_t k) {
        const auto [d, v0] = vertex_blocks[k];
        const Draw& draw = frame.draws[d];
        const auto n = static_cast<std::uint32_t>(front::vertex_count(draw));
        vertex_stage(draw, W, H, v0, std::min(n - v0, front::kVertexStageBlock) + v0,
                     vertex_caches[d]);
      }));
    }));
    vertex_edges.join();
  }
  return {vertex_caches.data(), frame.draws.size()};
}

// Bins the chunks again on `grid`, in parallel, and indexes them; returns the pairs binned.
std::uint64_t Renderer::Impl::rebin(std::span<bin::Chunk> binned, const bin::TileGrid& grid) {
  tbb::combinable<std::uint64_t> pairs;
  parallel::StageEdges edges;
  arena->execute(edges.task([&] {
    tbb::parallel_for(std::size_t{0}, binned.size(), edges.task([&](std::size_t i) {
      pairs.local() += bin::bin_chunk(binned[i], grid);
    }));
  }));
  edges.join();
  tile_chunks.build(binned, grid.count());
  return pairs.combine(std::plus<>());
}

FrameStats Renderer::Impl::render_fast(const Frame& frame, RenderTarget& target) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  FrameStats stats;
  stats.isa = isa;
  stats.threads = threads;
  const int W = target.width(), H = target.height(), S = target.samples();
  // The automatic tile size: by sample count, split into kSplitTileSize tiles for a frame whose
  // triangles reach fewer than kFewBusyTiles of those. A renderer that split its last frame of
  // this size bins the next on the split tiles first, since frames of a sequence look alike.
  const bin::TileGrid coarse(W, H, raster::tile_size_for(S));
  const bool split_last = last_split == std::tuple{W, H, S};
  bin::TileGrid grid(W, H,
                     options.tile_size ? options.tile_size
                     : split_last      ? bin::kSplitTileSize
                                       : coarse.size);

  // Draw state per draw; the painter's algorithm turns the depth test off everywhere. The
  // buffers the frame uses: colour if a draw writes it (or the target keeps it per sample),
  // depth if a draw tests or writes it.
  states.clear();
  bool any_color = false, any_depth = false;
  for (const Draw& d : frame.draws) {
    DrawState s = d.state;
    if (frame.painter) {
      s.depth_test = DepthTest::kAlways;
      s.depth_write = false;
    }
    any_color |= s.color_write;
    any_depth |= s.depth_test != DepthTest::kAlways || s.depth_write;
    states.push_back(s);
  }

  // Stage 1: the vertex stage.
  const std::span<const front::VertexCache> caches = project_vertices(frame, W, H);

  // Stages 2 and 3: front end and binning, in parallel over chunks of triangles. Each chunk is
  // binned into its own tile table right after it is set up, while its setups (256 bytes a
  // triangle) are still in this core's cache; a second pass read them back from memory
  // (random-small 4x: setup + binning 9.3 -> 6.4 ms on 1 thread, 4.3 -> 3.2 ms on 2). The
  // painter's algorithm needs a global sort by depth, so it sets the frame up in one chunk.
  if (frame.painter) {
    plan.single();
  } else {
    draw_triangles.clear();
    for (const Draw& d : frame.draws) draw_triangles.push_back(front::triangle_count(d));
    plan.build(draw_triangles, bin::kChunkTriangles);
  }
  const std::size_t nchunks = plan.chunks();
  if (chunks.size() < nchunks) chunks.resize(nchunks);
  tbb::combinable<front::FrontStats> front_stats;
  // Thread time of the chunks' setup and binning, which split the stage's wall time between
  // FrameStats::ms_setup and ms_binning.
  tbb::combinable<double> setup_thread_ms, binning_thread_ms;
  tbb::combinable<std::uint64_t> binned;
  const bool record = options.record_costs;
  if (record) stats.chunk_costs.assign(nchunks, {});
  auto bin_after = [&](std::size_t i, std::uint32_t triangles, Clock::time_point c0,
                       Clock::time_point c1) {
    binned.local() += bin::bin_chunk(chunks[i], grid);
    const auto c2 = Clock::now();
    setup_thread_ms.local() += ms_between(c0, c1);
    binning_thread_ms.local() += ms_between(c1, c2);
    if (record) stats.chunk_costs[i] = {triangles, ms_between(c0, c1), ms_between(c1, c2)};
  };

  const auto t_front = Clock::now();
  parallel::StageEdges front_edges;
  arena->execute(front_edges.task([&] {
    if (frame.painter) {
      chunks[0].planes.clear();
      chunks[0].draw_starts.clear();
      chunks[0].tris = reference::setup_frame(frame, W, H, S, stats, &chunks[0].planes);
      bin_after(0, 0, t_front, Clock::now());
    } else {
      tbb::parallel_for(std::size_t{0}, nchunks, front_edges.task([&](std::size_t i) {
        const auto c0 = Clock::now();
        const std::uint32_t triangles =
            bin::set_up_chunk(chunks[i], plan.pieces(i), frame.draws, front_end, W, H, S,
                              front_stats.local(), caches);
        bin_after(i, triangles, c0, Clock::now());
      }));
    }
  }));
  front_edges.join();
  bool bad_index = false;
  front_stats.combine_each([&](const front::FrontStats& fs) {
    fs.add_to(stats);
    bad_index = bad_index || fs.index_out_of_range;
  });
  if (bad_index) {
    // Nothing has touched the target yet: throw validate()'s error, naming the first bad index.
    validate(frame, target);
    throw Error(Errc::kIndexOutOfRange, "an index is past the last vertex of its draw");
  }
  start_loaded_samples(frame, target);
  stats.triangles_binned = binned.combine(std::plus<>());
  const auto t_binned = Clock::now();
  const double setup_share = setup_thread_ms.combine(std::plus<>()),
               binning_share = binning_thread_ms.combine(std::plus<>());
  double ms_binning =
      setup_share + binning_share > 0
          ? ms_between(t_front, t_binned) * binning_share / (setup_share + binning_share)
          : 0.0;
  const std::span<const bin::Chunk> binned_chunks(chunks.data(), nchunks);
  tile_chunks.build(binned_chunks, grid.count());
  if (options.tile_size == 0 && coarse.size > bin::kSplitTileSize) {
    const int coarse_busy = grid.size == coarse.size ? tile_chunks.busy_tiles()
                                                     : tile_chunks.busy_tiles_on(grid, coarse);
    const int wanted = coarse_busy < bin::kFewBusyTiles ? bin::kSplitTileSize : coarse.size;
    if (wanted != grid.size) {
      grid = bin::TileGrid(W, H, wanted);
      stats.triangles_binned = rebin({chunks.data(), nchunks}, grid);
      ms_binning += ms_between(t_binned, Clock::now());
    }
    last_split = grid.size == bin::kSplitTileSize ? std::tuple{W, H, S} : std::tuple{0, 0, 0};
  }
  stats.tile_size = grid.size;
  const auto t2 = Clock::now();

  // Stage 4: tiles, busiest first so the longest tile starts early; one worker owns a tile
  // from clear to resolve.
  tile_order.clear();
  for (int t = 0; t < grid.count(); ++t)
    tile_order.push_back({tile_chunks.triangles(binned_chunks, t), t});
  std::sort(tile_order.begin(), tile_order.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });

  raster::TileFrame tf;
  tf.states = states;
  shade::frame_shading(frame.draws, shading);
  tf.shading = shading;
  tf.samples = S;
  tf.ssaa = frame.ssaa;
  tf.tile_size = grid.size;
  tf.clear_color = target.clear_color();
  tf.clear_depth = target.clear_depth();
  tf.width = W;
  tf.height = H;
  tf.keep_color = any_color || target.options().keep_sample_color;
  tf.keep_depth = any_depth || frame.depth_load == LoadOp::kLoad;
  tf.load_color = frame.color_load == LoadOp::kLoad;
  tf.load_depth = frame.depth_load == LoadOp::kLoad;
  tf.occluders_nearest_first = frame.occluders_nearest_first;
  if (tf.keep_color) {
    const RenderTarget::ImageSurface image = target.image_surface();
    tf.image = image.base;
    tf.image_stride = image.stride_bytes;
    tf.image_bgra = image.bgra;
  } else if (!target.color_filled_with(tf.clear_color)) {
    // A depth-only frame: its image is the clear colour, written once for as long as it stays.
    target.fill_image(tf.clear_color);
    target.mark_color_filled(tf.clear_color);
  }
  if (frame.keep_hierarchical_z) {
    hiz.reset(W, H);
    tf.hiz_min = hiz.zmin_storage();
    tf.hiz_max = hiz.zmax_storage();
  } else {
    hiz.clear();
  }
  const std::size_t nsamples = static_cast<std::size_t>(W) * H * S;
  const RenderTarget::DepthSurface depth = target.depth_surface();
  tf.sample_depth = depth.base;
  tf.depth_stride = depth.stride_floats;
  if (target.options().keep_sample_color) {
    target.sample_color_storage().resize(nsamples);
    tf.sample_color = target.sample_color_storage().data();
  }
  tbb::combinable<raster::TileStats> tile_stats;
  if (record) stats.tile_costs.assign(static_cast<std::size_t>(grid.count()), {});
  // A task per tile with triangles, then the empty tiles (last in tile_order) in groups: their
  // work is a few row writes, which a task of its own would cost as much as.
  const auto busy_tiles = static_cast<std::size_t>(tile_chunks.busy_tiles());
  const std::size_t empty_tasks =
      (tile_order.size() - busy_tiles + kEmptyTilesPerTask - 1) / kEmptyTilesPerTask;
  const auto tiles_of_task = [&](std::size_t i) {
    if (i < busy_tiles) return std::pair{i, i + 1};
    const std::size_t first = busy_tiles + (i - busy_tiles) * kEmptyTilesPerTask;
    return std::pair{first, std::min(tile_order.size(), first + kEmptyTilesPerTask)};
  };
  // Without loads, the kernel writes an empty tile's clear values straight to the outputs, and
  // takes a rectangle of several tiles of a row at once (not when each tile's cost is recorded).
  const bool merge_empty = !tf.load_color && !tf.load_depth && !record;
  parallel::StageEdges tile_edges;
  arena->execute(tile_edges.task([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, busy_tiles + empty_tasks, 1),
        tile_edges.task([&](const tbb::blocked_range<std::size_t>& tasks) {
          Worker& worker =
              *workers[static_cast<std::size_t>(tbb::this_task_arena::current_thread_index())];
          const parallel::SlotHold hold(&worker);
          raster::TileScratch& sc = worker.scratch;
          std::vector<raster::BinRun>& bin = worker.runs;
          raster::TileStats& ts = tile_stats.local();
          const std::size_t k0 = tiles_of_task(tasks.begin()).first;
          const std::size_t k1 = tiles_of_task(tasks.end() - 1).second;
          for (std::size_t k = k0; k != k1; ++k) {
            const int t = tile_order[k].second;
            bin.clear();
            for (const bin::TileChunks::Entry& e : tile_chunks.of(t))
              bin::append_runs(chunks[e.chunk], e.bin, bin);
            const auto c0 = record ? Clock::now() : Clock::time_point{};
            raster::TileRect rect = grid.rect(t);
            if (merge_empty && k >= busy_tiles) {
              // Empty tiles next in the same tile row, up to kMaxTileSize wide: one write.
              while (k + 1 != k1 && tile_order[k + 1].second == tile_order[k].second + 1 &&
                     tile_order[k + 1].second % grid.tiles_x != 0 &&
                     rect.width + grid.size <= raster::kMaxTileSize) {
                rect.width += grid.rect(tile_order[++k].second).width;
              }
            }
            kernel(tf, rect, bin, sc, ts);
            if (record)
              stats.tile_costs[t] = {rect.x0,
                                     rect.y0,
                                     rect.width,
                                     rect.height,
                                     static_cast<std::uint32_t>(tile_order[k].first),
                                     ms_between(c0, Clock::now())};
          }
        }),
        tbb::simple_partitioner());
  }));
  tile_edges.join();
  if (frame.keep_hierarchical_z) hiz.build_coarse();
  const raster::TileStats ts =
      tile_stats.combine([](raster::TileStats a, const raster::TileStats& b) { return a += b; });
  stats.blocks_hiz_rejected = ts.blocks_hiz_rejected;
  stats.blocks_hiz_accepted = ts.blocks_hiz_accepted;
  stats.samples_tested = ts.samples_tested;
  stats.samples_written = ts.samples_written;
  stats.memory = frame_memory(caches, std::span<const bin::Chunk>(chunks.data(), nchunks));
  const auto t3 = Clock::now();

  stats.ms_setup = ms_between(t0, t2) - ms_binning;
  stats.ms_binning = ms_binning;
  stats.ms_raster = ms_between(t2, t3);
  stats.ms_resolve = static_cast<double>(ts.resolve_ns) * 1e-6;
  stats.ms_total = ms_between(t0, t3);
  return stats;
}

}  // namespace mosaic
