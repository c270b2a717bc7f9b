#include "soltex/raster/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "cap_tracer.h"
#include "edge_sampler.h"
#include "object_frame.h"
#include "screen_triangle.h"
#include "tile_kernels.h"
#include "tile_rasterizer.h"
#include "transformed_vertices.h"
#include "triangle_setup.h"
#include "worker_pool.h"

// A frame in three parallel passes:
//   1. vertices: every object's vertices transformed once (clip position, texture position in
//      double, world normal, clip-plane distances), in blocks;
//   2. setup: triangles in fixed chunks of the submission order, each chunk set up and binned
//      into tiles on its own (no shared state, no locks);
//   3. tiles: each tile drawn by one thread, visiting the chunks in order, so triangles are
//      drawn in submission order whatever the thread count; then resolved into the G-buffer.
namespace soltex {

using raster_internal::AffineForm;
using raster_internal::CapTracer;
using raster_internal::EdgeSampler;
using raster_internal::kTileSize;
using raster_internal::ObjectFrame;
using raster_internal::ScreenTriangle;
using raster_internal::ScreenTriangles;
using raster_internal::TileFrame;
using raster_internal::TileRasterizer;
using raster_internal::TransformedVertices;
using raster_internal::TriangleSetup;
using raster_internal::WorkerPool;

namespace {

constexpr std::size_t kVerticesPerBlock = 4096;
constexpr std::size_t kTrianglesPerChunk = 2048;
constexpr int kMaxThreads = 256;

// The screen triangles of one chunk of submitted triangles, and their tile bins: the
// triangles of tile t are bin_items[bin_start[t] .. bin_start[t + 1]), in submission order.
struct SetupChunk {
  ScreenTriangles triangles;
  std::vector<AffineForm> clip_forms;
  std::vector<uint32_t> bin_start;
  std::vector<uint32_t> bin_items;
  // Scratch of bin_triangles(), kept between frames: each triangle's tile when it lies in one,
  // and each bin's next free place.
  std::vector<uint32_t> single_tile;
  std::vector<uint32_t> bin_fill;
  RasterStats stats;
};

struct TileGrid {
  int columns = 0;
  int rows = 0;
  int count() const { return columns * rows; }
};

int resolve_thread_count(int requested) {
  if (requested < 0) {
    throw std::invalid_argument(
        "RasterOptions::threads must be >= 0 (0: one per hardware "
        "thread), got " +
        std::to_string(requested));
  }
  if (requested == 0) requested = static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(requested, 1, kMaxThreads);
}

void validate(const RasterView& view, std::span<const RasterObject> objects) {
  if (view.width < 1 || view.width > RasterView::kMaxSize || view.height < 1 ||
      view.height > RasterView::kMaxSize) {
    throw std::invalid_argument("RasterView size must be 1.." +
                                std::to_string(RasterView::kMaxSize) + " on each side, got " +
                                std::to_string(view.width) + "x" + std::to_string(view.height));
  }
  if (view.clip_planes.size() > RasterView::kMaxClipPlanes) {
    throw std::invalid_argument("RasterView has " + std::to_string(view.clip_planes.size()) +
                                " clip planes; at most " +
                                std::to_string(RasterView::kMaxClipPlanes) + " are supported");
  }
  for (std::size_t j = 0; j < view.clip_planes.size(); ++j) {
    const glm::dvec4& plane = view.clip_planes[j];
    const bool finite = std::isfinite(plane.x) && std::isfinite(plane.y) &&
                        std::isfinite(plane.z) && std::isfinite(plane.w);
    if (!finite || (plane.x == 0.0 && plane.y == 0.0 && plane.z == 0.0)) {
      throw std::invalid_argument("RasterView clip plane " + std::to_string(j) +
                                  " must be finite with a non-zero normal (a, b, c)");
    }
  }
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const RasterMesh& mesh = objects[i].mesh;
    if (mesh.indices.size() % 3 != 0) {
      throw std::invalid_argument("RasterObject " + std::to_string(i) + ": " +
                                  std::to_string(mesh.indices.size()) +
                                  " indices is not a multiple of 3");
    }
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) {
      throw std::invalid_argument("RasterObject " + std::to_string(i) + ": " +
                                  std::to_string(mesh.normals.size()) + " normals for " +
                                  std::to_string(mesh.positions.size()) +
                                  " positions (need one per position, or none)");
    }
    if (mesh.triangle_count() > UINT32_MAX / 3) {
      throw std::invalid_argument("RasterObject " + std::to_string(i) + " has too many triangles");
    }
  }
  if (objects.size() > UINT32_MAX) throw std::invalid_argument("too many RasterObjects");
}

// Sorts the chunk's triangles into tile bins (a counting sort, stable: submission order). A
// fine mesh's triangles mostly lie in one tile: the first pass notes that tile (or
// kSeveralTiles) per triangle, so the second writes it without walking the bounds again.
void bin_triangles(SetupChunk& chunk, const TileGrid& grid) {
  constexpr uint32_t kSeveralTiles = ~0u;
  chunk.bin_start.assign(static_cast<std::size_t>(grid.count()) + 1, 0);
  chunk.single_tile.resize(chunk.triangles.size());
  const auto for_each_tile = [&grid](const ScreenTriangle& t, auto&& visit) {
    for (int row = t.min_py / kTileSize; row <= t.max_py / kTileSize; ++row) {
      for (int column = t.min_px / kTileSize; column <= t.max_px / kTileSize; ++column) {
        visit(static_cast<std::size_t>(row * grid.columns + column));
      }
    }
  };
  for (std::size_t i = 0; i < chunk.triangles.size(); ++i) {
    const ScreenTriangle& t = chunk.triangles[i];
    // Bounds are clamped to the viewport: never negative, so the divisions are shifts.
    const int column = t.min_px / kTileSize, row = t.min_py / kTileSize;
    if (column == t.max_px / kTileSize && row == t.max_py / kTileSize) {
      const auto tile = static_cast<uint32_t>(row * grid.columns + column);
      chunk.single_tile[i] = tile;
      ++chunk.bin_start[tile + 1];
      continue;
    }
    chunk.single_tile[i] = kSeveralTiles;
    for_each_tile(t, [&](std::size_t tile) { ++chunk.bin_start[tile + 1]; });
  }
  for (std::size_t tile = 0; tile < static_cast<std::size_t>(grid.count()); ++tile) {
    chunk.bin_start[tile + 1] += chunk.bin_start[tile];
  }
  chunk.bin_items.resize(chunk.bin_start.back());
  chunk.bin_fill.assign(chunk.bin_start.begin(), chunk.bin_start.end() - 1);
  for (std::size_t i = 0; i < chunk.triangles.size(); ++i) {
    const uint32_t tile = chunk.single_tile[i];
    if (tile != kSeveralTiles) {
      chunk.bin_items[chunk.bin_fill[tile]++] = static_cast<uint32_t>(i);
      continue;
    }
    for_each_tile(chunk.triangles[i], [&](std::size_t other) {
      chunk.bin_items[chunk.bin_fill[other]++] = static_cast<uint32_t>(i);
    });
  }
}

}  // namespace

struct Rasterizer::Impl {
  explicit Impl(RasterOptions opts) : options(opts), pool(resolve_thread_count(opts.threads)) {
    for (int i = 0; i < pool.thread_count(); ++i) {
      tiles.push_back(std::make_unique<TileRasterizer>());
      setup_lanes.push_back(std::make_unique<raster_internal::SetupLanes>());
    }
    worker_stats.resize(static_cast<std::size_t>(pool.thread_count()));
    edge_samplers.resize(static_cast<std::size_t>(pool.thread_count()));
    tile_targets.resize(static_cast<std::size_t>(pool.thread_count()));
    for (GBuffer& tile : tile_targets) tile.resize(kTileSize, kTileSize, false);
    // Resolved from a tile with nothing drawn, so it holds exactly what resolving writes there.
    empty_tile.resize(kTileSize, kTileSize, false);
    TileRasterizer& nothing_drawn = *tiles.front();
    nothing_drawn.begin(0, 0, kTileSize, kTileSize);
    RasterStats unused;
    nothing_drawn.resolve(TileFrame{}, empty_tile, 0, 0, unused);
  }

  RasterOptions options;
  WorkerPool pool;
  // Kept between frames so that a steady scene renders without allocating.
  std::vector<ObjectFrame> objects;
  std::vector<std::size_t> first_triangle;  // per object, plus the total at the end
  TransformedVertices vertices;
  std::vector<SetupChunk> chunks;
  std::vector<std::unique_ptr<TileRasterizer>> tiles;                     // one per thread
  std::vector<std::unique_ptr<raster_internal::SetupLanes>> setup_lanes;  // one per thread
  std::vector<RasterStats> worker_stats;
  std::vector<GBuffer> tile_targets;  // one per thread, for render_tiles()
  // What render_tiles() hands over for a tile no triangle touches (most of a frame around a
  // single object): nothing to draw or resolve there.
  GBuffer empty_tile;
  // The last frame's tiling, chunks in use and caps, for sample_edges().
  TileGrid grid;
  std::size_t chunk_count = 0;
  int width = 0, height = 0;
  uint32_t beyond_planes = 0;  // the last frame's ObjectFrame::beyond_planes together
  std::optional<CapTracer> caps;
  std::vector<std::unique_ptr<EdgeSampler>> edge_samplers;  // per thread, each made when asked

  // A frame's first two steps: every object's vertices transformed and projected, then its
  // triangles set up and binned into `grid`'s tiles, chunk by chunk. Returns the chunk count.
  void transform_vertices(const RasterView& view, std::span<const RasterObject> sources,
                          const TriangleSetup& setup);
  std::size_t set_up_and_bin(std::span<const RasterObject> sources, const TriangleSetup& setup,
                             const TileGrid& grid);
};

static_assert(Rasterizer::kTileSize == kTileSize);

Rasterizer::Rasterizer(RasterOptions options) : impl_(std::make_unique<Impl>(options)) {}
Rasterizer::~Rasterizer() = default;
Rasterizer::Rasterizer(Rasterizer&&) noexcept = default;
Rasterizer& Rasterizer::operator=(Rasterizer&&) noexcept = default;

int Rasterizer::thread_count() const {
  return impl_->pool.thread_count();
}

void Rasterizer::parallel_for(std::size_t count,
                              const std::function<void(std::size_t, int)>& task) {
  impl_->pool.parallel_for(count, task);
}

RasterStats Rasterizer::render(const RasterView& view, std::span<const RasterObject> objects,
                               GBuffer& target) {
  return render(view, objects, target, TileCallback{});
}

RasterStats Rasterizer::render(const RasterView& view, std::span<const RasterObject> objects,
                               GBuffer& target, const TileCallback& after_tile) {
  validate(view, objects);
  target.resize(view.width, view.height, impl_->options.count_coverage);
  std::fill(target.coverage_count.begin(), target.coverage_count.end(), 0u);
  return draw(view, objects, &target, after_tile, TileGBufferCallback{});
}

RasterStats Rasterizer::render_tiles(const RasterView& view, std::span<const RasterObject> objects,
                                     const TileGBufferCallback& tile_done) {
  validate(view, objects);
  return draw(view, objects, nullptr, TileCallback{}, tile_done);
}

void Rasterizer::Impl::transform_vertices(const RasterView& view,
                                          std::span<const RasterObject> sources,
                                          const TriangleSetup& setup) {
  objects.clear();
  first_triangle.assign(1, 0);
  std::size_t vertex_count = 0;
  struct VertexBlock {
    std::size_t object, begin, end;
  };
  std::vector<VertexBlock> blocks;
  const uint32_t keeping_eye = raster_internal::planes_keeping_the_eye(view);
  for (std::size_t i = 0; i < sources.size(); ++i) {
    objects.push_back(
        raster_internal::make_object_frame(sources[i], view, vertex_count, keeping_eye));
    const std::size_t positions = sources[i].mesh.positions.size();
    for (std::size_t begin = 0; begin < positions; begin += kVerticesPerBlock) {
      blocks.push_back({i, begin, std::min(positions, begin + kVerticesPerBlock)});
    }
    vertex_count += positions;
    first_triangle.push_back(first_triangle.back() + sources[i].mesh.triangle_count());
  }
  vertices.resize(vertex_count, static_cast<int>(view.clip_planes.size()));
  pool.parallel_for(blocks.size(), [&](std::size_t b, int) {
    setup.transform_and_project(objects[blocks[b].object], blocks[b].begin, blocks[b].end,
                                vertices);
  });
}

std::size_t Rasterizer::Impl::set_up_and_bin(std::span<const RasterObject> sources,
                                             const TriangleSetup& setup, const TileGrid& grid) {
  const std::size_t triangle_count = first_triangle.back();
  const std::size_t chunk_count = (triangle_count + kTrianglesPerChunk - 1) / kTrianglesPerChunk;
  if (chunks.size() < chunk_count) chunks.resize(chunk_count);
  pool.parallel_for(chunk_count, [&](std::size_t c, int worker) {
    SetupChunk& chunk = chunks[c];
    chunk.triangles.clear();
    chunk.clip_forms.clear();
    chunk.stats = {};
    const std::size_t begin = c * kTrianglesPerChunk;
    const std::size_t end = std::min(triangle_count, begin + kTrianglesPerChunk);
    // The object holding triangle `begin`, then walk on, an object's part of the chunk at a
    // time.
    std::size_t object = static_cast<std::size_t>(
        std::upper_bound(first_triangle.begin(), first_triangle.end(), begin) -
        first_triangle.begin() - 1);
    raster_internal::SetupLanes& lanes = *setup_lanes[static_cast<std::size_t>(worker)];
    for (std::size_t global = begin; global < end;) {
      while (global >= first_triangle[object + 1]) ++object;
      const std::size_t part_end = std::min(end, first_triangle[object + 1]);
      const std::size_t local = global - first_triangle[object];
      setup.setup_range(objects[object], static_cast<uint32_t>(object), vertices,
                        sources[object].mesh.indices, local, local + (part_end - global), lanes,
                        chunk.triangles, chunk.clip_forms, chunk.stats);
      global = part_end;
    }
    bin_triangles(chunk, grid);
  });
  return chunk_count;
}

RasterStats Rasterizer::draw(const RasterView& view, std::span<const RasterObject> objects,
                             GBuffer* frame_target, const TileCallback& after_tile,
                             const TileGBufferCallback& tile_done) {
  Impl& impl = *impl_;
  const int plane_count = static_cast<int>(view.clip_planes.size());

  const TriangleSetup setup(view.width, view.height, plane_count, view.edge_sampling);
  impl.transform_vertices(view, objects, setup);
  const TileGrid grid{(view.width + kTileSize - 1) / kTileSize,
                      (view.height + kTileSize - 1) / kTileSize};
  const std::size_t chunk_count = impl.set_up_and_bin(objects, setup, grid);

  // Then the tiles, each drawn and resolved by the thread that takes it.
  impl.caps.reset();
  if (plane_count > 0) impl.caps.emplace(view);
  const std::optional<CapTracer>& caps = impl.caps;
  const TileFrame tile_frame{impl.objects, caps ? &*caps : nullptr};
  uint32_t beyond_planes = 0;
  for (const raster_internal::ObjectFrame& object : impl.objects) {
    beyond_planes |= object.beyond_planes;
  }
  impl.grid = grid;
  impl.beyond_planes = beyond_planes;
  impl.chunk_count = chunk_count;
  impl.width = view.width;
  impl.height = view.height;
  uint32_t* coverage = frame_target == nullptr || frame_target->coverage_count.empty()
                           ? nullptr
                           : frame_target->coverage_count.data();
  std::fill(impl.worker_stats.begin(), impl.worker_stats.end(), RasterStats{});
  const auto tile_is_empty = [&](std::size_t tile) {
    for (std::size_t c = 0; c < chunk_count; ++c) {
      if (impl.chunks[c].bin_start[tile + 1] != impl.chunks[c].bin_start[tile]) return false;
    }
    return true;
  };
  impl.pool.parallel_for(static_cast<std::size_t>(grid.count()), [&](std::size_t tile, int worker) {
    const int column = static_cast<int>(tile) % grid.columns;
    const int row = static_cast<int>(tile) / grid.columns;
    const int x0 = column * kTileSize, y0 = row * kTileSize;
    const int x1 = std::min(view.width, x0 + kTileSize), y1 = std::min(view.height, y0 + kTileSize);
    if (frame_target == nullptr && tile_is_empty(tile)) {
      if (tile_done) tile_done(impl.empty_tile, x0, y0, x1, y1, worker);
      return;
    }
    TileRasterizer& tiles = *impl.tiles[static_cast<std::size_t>(worker)];
    RasterStats& stats = impl.worker_stats[static_cast<std::size_t>(worker)];
    tiles.begin(x0, y0, x1, y1, beyond_planes);
    for (std::size_t c = 0; c < chunk_count; ++c) {
      const SetupChunk& chunk = impl.chunks[c];
      const uint32_t begin = chunk.bin_start[tile], end = chunk.bin_start[tile + 1];
      if (begin == end) continue;
      tiles.draw_bin(chunk.triangles.data(),
                     std::span<const uint32_t>(chunk.bin_items).subspan(begin, end - begin),
                     chunk.clip_forms, coverage, view.width, stats);
    }
    if (frame_target != nullptr) {
      tiles.resolve(tile_frame, *frame_target, 0, 0, stats);
      if (after_tile) after_tile(x0, y0, x1, y1, worker);
    } else {
      GBuffer& tile_target = impl.tile_targets[static_cast<std::size_t>(worker)];
      tiles.resolve(tile_frame, tile_target, x0, y0, stats);
      if (tile_done) tile_done(tile_target, x0, y0, x1, y1, worker);
    }
  });

  RasterStats total;
  for (std::size_t c = 0; c < chunk_count; ++c) total += impl.chunks[c].stats;
  for (const RasterStats& stats : impl.worker_stats) total += stats;
  return total;
}

void Rasterizer::sample_edges(int x0, int y0, std::span<const glm::ivec2> pixels, int grid,
                              int worker, EdgeSurfaces& out) {
  Impl& impl = *impl_;
  if (x0 < 0 || y0 < 0 || x0 % kTileSize != 0 || y0 % kTileSize != 0 || x0 >= impl.width ||
      y0 >= impl.height) {
    throw std::invalid_argument("sample_edges: (" + std::to_string(x0) + ", " + std::to_string(y0) +
                                ") is not a tile corner of the last frame");
  }
  if (worker < 0 || worker >= impl.pool.thread_count() ||
      !impl.tiles[static_cast<std::size_t>(worker)]->began_at(x0, y0)) {
    throw std::invalid_argument("sample_edges: render thread " + std::to_string(worker) +
                                " did not just draw the tile at (" + std::to_string(x0) + ", " +
                                std::to_string(y0) + ")");
  }
  auto& sampler = impl.edge_samplers[static_cast<std::size_t>(worker)];
  if (!sampler) sampler = std::make_unique<EdgeSampler>();
  const int x1 = std::min(impl.width, x0 + kTileSize), y1 = std::min(impl.height, y0 + kTileSize);
  sampler->begin(x0, y0, x1, y1, pixels, grid, impl.beyond_planes);
  const auto tile = static_cast<std::size_t>((y0 / kTileSize) * impl.grid.columns + x0 / kTileSize);
  for (std::size_t c = 0; c < impl.chunk_count; ++c) {
    const SetupChunk& chunk = impl.chunks[c];
    const uint32_t end = chunk.bin_start[tile + 1];
    for (uint32_t k = chunk.bin_start[tile]; k < end; ++k) {
      if (k + raster_internal::kBinPrefetchAhead < end) {
        __builtin_prefetch(
            &chunk.triangles[chunk.bin_items[k + raster_internal::kBinPrefetchAhead]]);
      }
      sampler->draw(chunk.triangles[chunk.bin_items[k]], chunk.clip_forms);
    }
  }
  sampler->resolve(TileFrame{impl.objects, impl.caps ? &*impl.caps : nullptr}, out);
}

}  // namespace soltex
