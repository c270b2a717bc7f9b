#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <glm/vec3.hpp>
#include <span>

// Batch forms of the sampling kernels (cell split and RGB trilinear), compiled for every
// Highway target and chosen at run time, once per call: a generic binary runs AVX2 or
// AVX-512 code where the CPU has it. Each call handles up to kSampleChunk points; callers
// loop over chunks. Results are bit-identical to split_cell_scalar() and
// trilinear_detail::scalar<3>() on every target.
namespace soltex {

inline constexpr std::size_t kSampleChunk = 64;
// What a caller that groups points for TextureSampler's batch call hands over at a time: a
// batch of several chunks is looked up one chunk ahead, each chunk's samples coming from memory
// while the chunk before is filtered.
inline constexpr std::size_t kSampleBatch = 8 * kSampleChunk;

// Where up to kSampleChunk points fall in a lattice, per axis (structure of arrays), and,
// after locate_cells(), in which brick and where inside it.
struct CellChunk {
  alignas(64) std::array<std::array<int32_t, kSampleChunk>, 3> cell;
  alignas(64) std::array<std::array<float, kSampleChunk>, 3> frac;
  alignas(64) std::array<int32_t, kSampleChunk> brick;   // (bz * n + by) * n + bx
  alignas(64) std::array<int32_t, kSampleChunk> offset;  // bytes from the brick's first sample
};

// How a lattice is cut into bricks: brick = cell >> shift, local = cell & mask, `bricks` per
// axis (bricks^3 must fit an int32), samples of `channels` bytes with the given strides.
struct BrickGeometry {
  int shift;
  int mask;
  int bricks;
  int channels;
  std::ptrdiff_t y_stride;
  std::ptrdiff_t z_stride;
};

// split_cell_scalar(points[i], origin, spacing, scale, cells) for each i into chunk.cell[*][i]
// and chunk.frac[*][i]. points.size() <= kSampleChunk.
void split_cells(std::span<const glm::dvec3> points, const glm::dvec3& origin,
                 const glm::dvec3& spacing, double scale, double cells, CellChunk& chunk);

// chunk.brick[i] and chunk.offset[i] from chunk.cell[*][i] for i < n (n <= kSampleChunk):
// the brick's flat index and the byte offset of the cell's first sample in it.
void locate_cells(CellChunk& chunk, std::size_t n, const BrickGeometry& geometry);

// The four sample rows of up to kSampleChunk cells of a 3-channel lattice, as the batch RGB
// kernel reads them: row[r][i] holds the 8 bytes from cell i's corner sample in row r (0: at
// y and z, 1: y + 1, 2: z + 1, 3: both), samples x and x + 1 and two bytes of the padding
// (kTrilinearLoadPadding), in memory order (little-endian). Read once per cell, so that the
// kernel can turn each channel of each corner into one vector of points.
struct CellRows {
  alignas(64) std::array<std::array<uint64_t, kSampleChunk>, 4> row;

  void read(std::size_t i, const uint8_t* corner, std::ptrdiff_t y_stride,
            std::ptrdiff_t z_stride) {
    std::memcpy(&row[0][i], corner, sizeof(uint64_t));
    std::memcpy(&row[1][i], corner + y_stride, sizeof(uint64_t));
    std::memcpy(&row[2][i], corner + z_stride, sizeof(uint64_t));
    std::memcpy(&row[3][i], corner + y_stride + z_stride, sizeof(uint64_t));
  }
};

// For each i < n: the RGB trilinear lookup of trilinear_u8<3> over rows.row[*][i] and fractions
// chunk.frac[*][i], written as four floats (R, G, B, 0) at out + i * out_stride. n <=
// kSampleChunk.
void trilinear_rgb_rows(const CellRows& rows, const CellChunk& chunk, std::size_t n, float* out,
                        std::size_t out_stride);

// For each i with corners[i] != nullptr: the RGB trilinear lookup of trilinear_u8<3> at corner
// sample corners[i] and fractions chunk.frac[*][i], written as four floats (R, G, B, 0) at
// out + i * out_stride. corners.size() <= kSampleChunk.
void trilinear_rgb(std::span<const uint8_t* const> corners, const CellChunk& chunk,
                   std::ptrdiff_t y_stride, std::ptrdiff_t z_stride, float* out,
                   std::size_t out_stride);

}  // namespace soltex
