#include "soltex/scene/obj_loader.h"

#include <tiny_obj_loader.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

#include "mesh_cleanup.h"
#include "polygon_triangulation.h"

namespace soltex {
namespace {

std::string trimmed(std::string text) {
  const std::size_t end = text.find_last_not_of(" \t\r\n.");
  text.erase(end == std::string::npos ? 0 : end + 1);
  return text;
}

}  // namespace

ObjError::ObjError(std::string file, std::string problem)
    : std::runtime_error(file + ": " + problem),
      file_(std::move(file)),
      problem_(std::move(problem)) {}

LoadedObj parse_obj(std::string_view text, const std::string& name_for_errors,
                    const ObjLoadOptions& options) {
  // tinyobjloader's own triangulation skips faces with bad indices silently and its ear
  // clipping can fold non-convex polygons; read raw faces, check them, triangulate here.
  tinyobj::ObjReaderConfig config;
  config.triangulate = false;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(std::string(text), std::string(), config)) {
    const std::string error = trimmed(reader.Error());
    throw ObjError(name_for_errors, error.empty() ? "not a valid OBJ file" : error);
  }

  LoadedObj result;
  ObjLoadStats& stats = result.stats;
  Mesh& mesh = result.mesh;
  const std::vector<tinyobj::real_t>& coordinates = reader.GetAttrib().vertices;
  const std::size_t vertex_count = coordinates.size() / 3;
  if (vertex_count > std::numeric_limits<uint32_t>::max()) {
    throw ObjError(name_for_errors,
                   std::to_string(vertex_count) + " vertices: at most 2^32 - 1 can be indexed");
  }
  stats.vertices_read = vertex_count;
  mesh.positions.resize(vertex_count);
  for (std::size_t i = 0; i < vertex_count; ++i) {
    const glm::vec3 p(coordinates[3 * i], coordinates[3 * i + 1], coordinates[3 * i + 2]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw ObjError(name_for_errors,
                     "vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
    }
    mesh.positions[i] = p;
  }

  std::vector<uint32_t> polygon;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    std::size_t next = 0;
    for (const unsigned int corners : shape.mesh.num_face_vertices) {
      ++stats.faces_read;
      polygon.clear();
      for (unsigned int k = 0; k < corners; ++k) {
        const int index = shape.mesh.indices[next + k].vertex_index;
        if (index < 0 || static_cast<std::size_t>(index) >= vertex_count) {
          // tinyobjloader has made relative (negative) indices absolute; still negative means
          // the file pointed before its first vertex.
          throw ObjError(name_for_errors,
                         "face " + std::to_string(stats.faces_read) +
                             (index < 0 ? " uses a relative index before the first vertex"
                                        : " refers to vertex " + std::to_string(index + 1) +
                                              ", but the file defines only " +
                                              std::to_string(vertex_count) + " vertices"));
        }
        polygon.push_back(static_cast<uint32_t>(index));
      }
      next += corners;
      if (corners > 3) ++stats.polygons_triangulated;
      triangulate_polygon(mesh.positions, polygon, mesh.indices);
    }
  }
  if (stats.faces_read == 0) {
    throw ObjError(name_for_errors,
                   "no faces (" + std::to_string(vertex_count) + " vertices): not a surface mesh");
  }

  stats.duplicate_vertices_merged = merge_duplicate_vertices(mesh);
  stats.degenerate_triangles_dropped = drop_degenerate_triangles(mesh);
  stats.unreferenced_vertices_removed = remove_unreferenced_vertices(mesh);
  if (mesh.triangle_count() == 0) {
    throw ObjError(name_for_errors,
                   "all " + std::to_string(stats.faces_read) + " faces are degenerate (zero area)");
  }
  compute_vertex_normals(mesh);
  if (options.normalize) {
    normalize_to_unit_box(mesh);
  } else {
    mesh.update_bounds();
  }
  return result;
}

LoadedObj load_obj(const std::filesystem::path& path, const ObjLoadOptions& options) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw ObjError(path.string(), "is a directory, not an OBJ file");
  }
  // Regular files of bounded size only: a device or a huge file must not exhaust memory.
  if (std::filesystem::exists(path, error) && !std::filesystem::is_regular_file(path, error)) {
    throw ObjError(path.string(), "is not a regular file");
  }
  constexpr std::uintmax_t kMaxObjBytes = 512ull << 20;
  if (const std::uintmax_t size = std::filesystem::file_size(path, error);
      !error && size > kMaxObjBytes) {
    throw ObjError(path.string(), std::to_string(size) + " bytes: OBJ files are limited to " +
                                      std::to_string(kMaxObjBytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ObjError(path.string(), std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ObjError(path.string(), std::string("cannot read: ") + std::strerror(errno));
  return parse_obj(text.str(), path.string(), options);
}

}  // namespace soltex
