#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

// The texture core's view of a texture defined by a node graph. The graph module
// (common/graph, soltex::graph) compiles graphs into GraphField objects; the core only evaluates
// them, asks which channels they output and hashes them, so it needs nothing of nodes.
namespace soltex {

struct Grid;
struct ChannelSet;

// Where evaluated channels go: planes of `count` floats, nullptr for a channel not wanted.
// Colour is three planes (R, G, B); opacity and specular are the graph's scalar outputs in
// [0, 1] before the spec's ScalarRange maps them.
struct GraphPlanes {
  float* colour[3] = {nullptr, nullptr, nullptr};
  float* opacity = nullptr;
  float* specular = nullptr;
};

class GraphField {
 public:
  virtual ~GraphField() = default;

  // The channels the graph defines an output for.
  virtual bool has_colour() const = 0;
  virtual bool has_opacity() const = 0;
  virtual bool has_specular() const = 0;

  // Appends the graph's canonical form: equal for graphs that differ only in node names or
  // order, so the texture id does not depend on them.
  virtual void append_canonical(std::vector<uint8_t>& bytes) const = 0;

  // Noise octaves evaluated per sample at this filter width (for the octave counters).
  virtual int evaluated_octaves(double filter_width) const = 0;

  // out planes hold points.size() floats; widths[i] is points[i]'s filter width.
  virtual void evaluate_points(std::span<const glm::dvec3> points, std::span<const double> widths,
                               const GraphPlanes& out) const = 0;

  // Over a grid (x fastest) at one filter width; planes hold grid.size() floats. Bit-identical
  // to evaluate_points at the grid's points.
  virtual void evaluate_grid(const Grid& grid, double filter_width,
                             const GraphPlanes& out) const = 0;
};

}  // namespace soltex
