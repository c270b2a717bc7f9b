#pragma once

#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "soltex/scene/mesh.h"

// Wavefront OBJ files as they come: coordinates are read in double and stay double until the
// mesh is normalised, so a model far from the origin keeps its shape; a face using a vertex
// that is not three finite numbers is an error naming both lines; polygons of any size up to
// kMaxFaceVertices are ear-clipped, exact duplicate vertices are
// merged, degenerate triangles (a repeated vertex or zero area) are dropped, unreferenced
// vertices are removed, and smooth normals are computed from the positions (any normals in
// the file are ignored: many real files have none or wrong ones). Materials, texture
// coordinates and groups are ignored; all groups become one mesh.
namespace soltex {

// The file (or the name given for a string) and what is wrong with it.
class ObjError : public std::runtime_error {
 public:
  ObjError(std::string file, std::string problem);

  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  std::string problem_;
};

// More vertices than this in one face is refused: ear clipping costs O(n^2) in the worst case
// (a comb of this many vertices takes about 0.15 s), and no real model has faces anywhere
// near this large.
inline constexpr std::size_t kMaxFaceVertices = 16384;

// A cube's or a machined part's edges (90 degrees) stay sharp; a scan's or a tessellated
// curve's gentle bends (a 32-sided cylinder: 11.25) stay smooth.
inline constexpr double kDefaultCreaseDegrees = 60.0;

struct ObjLoadOptions {
  bool normalize = false;  // see normalize_to_unit_box()
  // Faces meeting at more than this keep a hard edge (compute_creased_normals()); 180: every
  // vertex smooth.
  double crease_degrees = kDefaultCreaseDegrees;
};

// What loading did to the file's contents, for logs and tests.
struct ObjLoadStats {
  std::size_t vertices_read = 0;
  std::size_t faces_read = 0;
  std::size_t polygons_triangulated = 0;  // faces with more than three vertices
  std::size_t degenerate_triangles_dropped = 0;
  // Faces over the same vertices as an earlier one, and of those the ones wound the other way
  // (a two-sided face written once each way).
  std::size_t duplicate_faces_dropped = 0;
  std::size_t reversed_faces_dropped = 0;
  std::size_t duplicate_vertices_merged = 0;
  std::size_t unreferenced_vertices_removed = 0;
  std::size_t vertices_split_at_creases = 0;  // one copy per extra normal at a hard edge
};

struct LoadedObj {
  Mesh mesh;
  ObjLoadStats stats;
};

LoadedObj load_obj(const std::filesystem::path& path, const ObjLoadOptions& options = {});

// The same from text; name_for_errors stands for the file in messages.
LoadedObj parse_obj(std::string_view text, const std::string& name_for_errors,
                    const ObjLoadOptions& options = {});

}  // namespace soltex
