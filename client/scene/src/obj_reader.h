#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "soltex/scene/obj_loader.h"

// The two statements of a Wavefront OBJ file that make a surface, `v` and `f`, read in double
// with the line each came from. Everything else (normals, texture coordinates, groups,
// materials, lines, points) is skipped.
//
// Why not tinyobjloader: its number parser turns "nan", "inf" and any unreadable coordinate
// into 0 without a word, it is not correctly rounded in double ("0.3" reads as
// 0.30000000000000004), and it stores a face's vertex count in an unsigned char, so a face of
// 256 or more vertices silently takes the following faces' vertices. std::from_chars is
// correctly rounded and says when a token is not a number.
namespace soltex {

struct ObjText {
  // One per `v` statement, in order. A vertex whose x, y and z are not three finite numbers
  // holds NaN here; it is an error only if a face uses it (see bad_vertex_problem).
  std::vector<glm::dvec3> positions;
  std::vector<uint32_t> bad_vertices;  // indices of the NaN-holding vertices, ascending
  std::vector<std::size_t> bad_vertex_lines;
  std::vector<std::string> bad_vertex_texts;  // the statement as written, shortened

  // Faces: face_sizes[f] corners each, their 0-based vertex indices one after another in
  // `corners` (relative indices already made absolute), and the line each face is on.
  std::vector<uint32_t> corners;
  std::vector<uint32_t> face_sizes;
  std::vector<std::size_t> face_lines;
};

// Reads `text`; a face with an index that is not a number, zero, or before the first vertex,
// or with more than kMaxFaceVertices vertices, throws ObjError naming name_for_errors and the
// line. Indices past the last vertex are left for the caller, which knows the final count.
ObjText read_obj_text(std::string_view text, const std::string& name_for_errors);

}  // namespace soltex
