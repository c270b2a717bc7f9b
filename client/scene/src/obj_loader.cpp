#include "soltex/scene/obj_loader.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <glm/common.hpp>
#include <limits>
#include <span>
#include <sstream>
#include <utility>

#include "mesh_cleanup.h"
#include "obj_reader.h"
#include "polygon_triangulation.h"

namespace soltex {
namespace {

// The OBJ file's vertices, in double until they are normalised.
struct WideMesh {
  std::vector<glm::dvec3> positions;
  std::vector<uint32_t> indices;
};

void count_repeats(const RepeatedFaces& repeats, ObjLoadStats& stats) {
  stats.duplicate_faces_dropped += repeats.count;
  stats.reversed_faces_dropped += repeats.reversed;
}

// Checks every face's indices against the final vertex count and the vertices it uses for
// finite coordinates, and triangulates it.
void triangulate_faces(const ObjText& obj, const std::string& name, WideMesh& mesh,
                       ObjLoadStats& stats) {
  const std::size_t vertex_count = obj.positions.size();
  // Polygons over the same vertices (a face written once each way): kept once, here, since
  // their triangulations need not share a diagonal for drop_duplicate_triangles() to find.
  const RepeatedFaces repeats = find_repeated_polygons(obj.corners, obj.face_sizes);
  stats.duplicate_faces_dropped = repeats.count;
  stats.reversed_faces_dropped = repeats.reversed;
  std::size_t next = 0;
  for (std::size_t f = 0; f < obj.face_sizes.size(); ++f) {
    ++stats.faces_read;
    const std::span<const uint32_t> polygon(obj.corners.data() + next, obj.face_sizes[f]);
    next += obj.face_sizes[f];
    for (const uint32_t index : polygon) {
      const auto face = [&] {
        return "line " + std::to_string(obj.face_lines[f]) + ": face " + std::to_string(f + 1);
      };
      if (index >= vertex_count) {
        throw ObjError(name, face() + " refers to vertex " + std::to_string(index + 1ull) +
                                 ", but the file defines only " + std::to_string(vertex_count) +
                                 " vertices");
      }
      if (std::isnan(obj.positions[index].x)) {
        const auto bad = std::lower_bound(obj.bad_vertices.begin(), obj.bad_vertices.end(), index);
        const std::size_t k = static_cast<std::size_t>(bad - obj.bad_vertices.begin());
        throw ObjError(name, face() + " uses vertex " + std::to_string(index + 1ull) +
                                 ", which is not three finite numbers: line " +
                                 std::to_string(obj.bad_vertex_lines[k]) + " reads \"" +
                                 obj.bad_vertex_texts[k] + "\"");
      }
    }
    if (repeats.repeated[f]) continue;
    if (polygon.size() > 3) ++stats.polygons_triangulated;
    triangulate_polygon(obj.positions, polygon, mesh.indices);
  }
}

// normalize_to_unit_box() in double, where the file's coordinates are exact: a model 1e9 from
// the origin lands on the same float positions as the same model at the origin.
void normalize_wide(std::vector<glm::dvec3>& positions) {
  glm::dvec3 lo = positions.front(), hi = positions.front();
  for (const glm::dvec3& p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  // Halves first: hi - lo can overflow a double, hi / 2 - lo / 2 cannot.
  const glm::dvec3 half = 0.5 * hi - 0.5 * lo;
  const glm::dvec3 centre = 0.5 * hi + 0.5 * lo;
  const double longest_half = std::max({half.x, half.y, half.z});
  const double scale = longest_half > 0.0 ? 1.0 / longest_half : 1.0;
  for (glm::dvec3& p : positions) p = (p - centre) * scale;
}

// The float mesh; without normalising, a coordinate beyond float's range is refused.
Mesh to_float_mesh(WideMesh wide, const std::string& name, bool normalize) {
  if (normalize) normalize_wide(wide.positions);
  Mesh mesh;
  mesh.positions.reserve(wide.positions.size());
  for (const glm::dvec3& p : wide.positions) {
    const glm::vec3 narrow(p);
    if (!std::isfinite(narrow.x) || !std::isfinite(narrow.y) || !std::isfinite(narrow.z)) {
      char where[96];
      std::snprintf(where, sizeof where, "(%.9g, %.9g, %.9g)", p.x, p.y, p.z);
      throw ObjError(name, std::string("a vertex at ") + where +
                               " is beyond float range (3.4e38); load the mesh with normalize");
    }
    mesh.positions.push_back(narrow);
  }
  mesh.indices = std::move(wide.indices);
  return mesh;
}

}  // namespace

ObjError::ObjError(std::string file, std::string problem)
    : std::runtime_error(file + ": " + problem),
      file_(std::move(file)),
      problem_(std::move(problem)) {}

LoadedObj parse_obj(std::string_view text, const std::string& name_for_errors,
                    const ObjLoadOptions& options) {
  ObjText obj = read_obj_text(text, name_for_errors);
  LoadedObj result;
  ObjLoadStats& stats = result.stats;
  const std::size_t vertex_count = obj.positions.size();
  if (vertex_count > std::numeric_limits<uint32_t>::max()) {
    throw ObjError(name_for_errors,
                   std::to_string(vertex_count) + " vertices: at most 2^32 - 1 can be indexed");
  }
  stats.vertices_read = vertex_count;
  if (obj.face_sizes.empty()) {
    throw ObjError(name_for_errors,
                   "no faces (" + std::to_string(vertex_count) + " vertices): not a surface mesh");
  }

  // Faces of one or two vertices (a point or a line written as "f") make no triangle; a file of
  // nothing else is named for what it holds, not as zero-area faces.
  const std::size_t too_small = static_cast<std::size_t>(std::count_if(
      obj.face_sizes.begin(), obj.face_sizes.end(), [](uint32_t n) { return n < 3; }));
  if (too_small == obj.face_sizes.size()) {
    throw ObjError(name_for_errors, "line " + std::to_string(obj.face_lines.front()) +
                                        ": every face has fewer than 3 vertices (" +
                                        std::to_string(too_small) +
                                        " faces): a face needs 3, a line is \"l\"");
  }
  WideMesh wide;
  triangulate_faces(obj, name_for_errors, wide, stats);
  wide.positions = std::move(obj.positions);
  obj = {};
  // Cleaned in double, then again in float: points apart in the file can meet in float.
  stats.duplicate_vertices_merged = merge_duplicate_vertices(wide.positions, wide.indices);
  stats.degenerate_triangles_dropped = drop_degenerate_triangles(wide.positions, wide.indices);
  stats.unreferenced_vertices_removed = remove_unreferenced_vertices(wide.positions, wide.indices);
  if (wide.indices.empty()) {
    throw ObjError(name_for_errors,
                   "all " + std::to_string(stats.faces_read) + " faces are degenerate (zero area)");
  }
  Mesh& mesh = result.mesh;
  mesh = to_float_mesh(std::move(wide), name_for_errors, options.normalize);
  stats.duplicate_vertices_merged += merge_duplicate_vertices(mesh.positions, mesh.indices);
  stats.degenerate_triangles_dropped += drop_degenerate_triangles(mesh.positions, mesh.indices);
  // Once, after both merges: a triangle repeated over vertices merged in double is repeated
  // over those in float too.
  count_repeats(drop_duplicate_triangles(mesh.indices), stats);
  stats.unreferenced_vertices_removed += remove_unreferenced_vertices(mesh.positions, mesh.indices);
  if (mesh.triangle_count() == 0) {
    throw ObjError(name_for_errors, "all " + std::to_string(stats.faces_read) +
                                        " faces are degenerate (zero area) in float precision");
  }
  mesh.two_sided = stats.reversed_faces_dropped > 0;
  stats.vertices_split_at_creases = compute_creased_normals(mesh, options.crease_degrees);
  mesh.update_bounds();
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
