#include "soltex/common/brick_filter.h"

#include <cstddef>
#include <stdexcept>
#include <string>

namespace soltex {
namespace {

struct FilterAxes {
  bool x = false;
  bool y = false;
  bool z = false;
};

FilterAxes axes_of(BrickFilter filter) {
  switch (filter) {
    case BrickFilter::none: return {};
    case BrickFilter::delta_x: return {true, false, false};
    case BrickFilter::gradient_xy: return {true, true, false};
    case BrickFilter::gradient_3d: return {true, true, true};
  }
  throw std::invalid_argument("brick filter id " + std::to_string(static_cast<int>(filter)) +
                              " is unknown: ids go up to " + std::to_string(kMaxBrickFilterId));
}

std::size_t checked_plane_size(int side, std::size_t total) {
  if (side < 1) {
    throw std::invalid_argument("brick filter: side = " + std::to_string(side) +
                                " must be at least 1");
  }
  const auto s = static_cast<std::size_t>(side);
  const std::size_t plane = s * s * s;
  if (total % plane != 0) {
    throw std::invalid_argument("brick filter: " + std::to_string(total) +
                                " samples are not a whole number of " + std::to_string(plane) +
                                "-sample planes");
  }
  return plane;
}

// dst[i] -= src[i] over n bytes, mod 256.
void subtract(uint8_t* dst, const uint8_t* src, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<uint8_t>(dst[i] - src[i]);
}

void add(uint8_t* dst, const uint8_t* src, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<uint8_t>(dst[i] + src[i]);
}

// Backward differences run from the far end so each one still reads an unfiltered neighbour.
void difference_plane(const FilterAxes& axes, std::size_t side, uint8_t* plane) {
  const std::size_t slab = side * side;
  if (axes.z) {
    for (std::size_t z = side - 1; z >= 1; --z) subtract(plane + z * slab, plane + (z - 1) * slab, slab);
  }
  if (axes.y) {
    for (std::size_t z = 0; z < side; ++z) {
      uint8_t* s = plane + z * slab;
      for (std::size_t y = side - 1; y >= 1; --y) subtract(s + y * side, s + (y - 1) * side, side);
    }
  }
  if (axes.x) {
    for (std::size_t row = 0; row < slab; ++row) {
      uint8_t* r = plane + row * side;
      for (std::size_t x = side - 1; x >= 1; --x) r[x] = static_cast<uint8_t>(r[x] - r[x - 1]);
    }
  }
}

// Prefix sums from the near end: each one reads a neighbour that is already restored.
void integrate_plane(const FilterAxes& axes, std::size_t side, uint8_t* plane) {
  const std::size_t slab = side * side;
  if (axes.x) {
    for (std::size_t row = 0; row < slab; ++row) {
      uint8_t* r = plane + row * side;
      for (std::size_t x = 1; x < side; ++x) r[x] = static_cast<uint8_t>(r[x] + r[x - 1]);
    }
  }
  if (axes.y) {
    for (std::size_t z = 0; z < side; ++z) {
      uint8_t* s = plane + z * slab;
      for (std::size_t y = 1; y < side; ++y) add(s + y * side, s + (y - 1) * side, side);
    }
  }
  if (axes.z) {
    for (std::size_t z = 1; z < side; ++z) add(plane + z * slab, plane + (z - 1) * slab, slab);
  }
}

}  // namespace

const char* brick_filter_name(BrickFilter filter) {
  switch (filter) {
    case BrickFilter::none: return "none";
    case BrickFilter::delta_x: return "delta-x";
    case BrickFilter::gradient_xy: return "gradient-xy";
    case BrickFilter::gradient_3d: return "gradient-3d";
  }
  return "unknown";
}

void apply_brick_filter(BrickFilter filter, int side, std::span<uint8_t> planes) {
  const FilterAxes axes = axes_of(filter);
  const std::size_t plane = checked_plane_size(side, planes.size());
  for (std::size_t offset = 0; offset < planes.size(); offset += plane) {
    difference_plane(axes, static_cast<std::size_t>(side), planes.data() + offset);
  }
}

void undo_brick_filter(BrickFilter filter, int side, std::span<uint8_t> planes) {
  const FilterAxes axes = axes_of(filter);
  const std::size_t plane = checked_plane_size(side, planes.size());
  for (std::size_t offset = 0; offset < planes.size(); offset += plane) {
    integrate_plane(axes, static_cast<std::size_t>(side), planes.data() + offset);
  }
}

}  // namespace soltex
