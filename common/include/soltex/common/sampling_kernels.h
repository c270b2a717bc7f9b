#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>

// Batch forms of the sampling kernels (cell split and RGB trilinear), compiled for every
// Highway target and chosen at run time, once per call: a generic binary runs AVX2 or
// AVX-512 code where the CPU has it. Each call handles up to kSampleChunk points; callers
// loop over chunks. Results are bit-identical to split_cell_scalar() and
// trilinear_detail::scalar<3>() on every target.
namespace soltex {

inline constexpr std::size_t kSampleChunk = 64;

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

// For each i with corners[i] != nullptr: the RGB trilinear lookup of trilinear_u8<3> at corner
// sample corners[i] and fractions chunk.frac[*][i], written as four floats (R, G, B, 0) at
// out + i * out_stride. corners.size() <= kSampleChunk.
void trilinear_rgb(std::span<const uint8_t* const> corners, const CellChunk& chunk,
                   std::ptrdiff_t y_stride, std::ptrdiff_t z_stride, float* out,
                   std::size_t out_stride);

}  // namespace soltex
