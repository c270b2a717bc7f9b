#include "soltex/scene/obj_loader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <string>
#include <vector>

#include "soltex/scene/builtin_meshes.h"

namespace soltex {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

ObjError obj_error_of(std::string_view text, const std::string& name = "bad.obj") {
  try {
    (void)parse_obj(text, name);
  } catch (const ObjError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an ObjError";
  return ObjError("", "");
}

float triangle_area(const Mesh& mesh, std::size_t t) {
  const glm::vec3 a = mesh.positions[mesh.indices[3 * t]];
  const glm::vec3 b = mesh.positions[mesh.indices[3 * t + 1]];
  const glm::vec3 c = mesh.positions[mesh.indices[3 * t + 2]];
  return 0.5f * glm::length(glm::cross(b - a, c - a));
}

void expect_unit_normals(const Mesh& mesh) {
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (const glm::vec3& n : mesh.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

// A writable file that is removed again at the end of the test.
class TempFile {
 public:
  TempFile(const std::string& name, std::string_view contents)
      : path_(std::filesystem::temp_directory_path() /
              ("soltex-" + std::to_string(::getpid()) + "-" + name)) {
    std::ofstream(path_, std::ios::binary) << contents;
  }
  ~TempFile() { std::filesystem::remove(path_); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

constexpr const char* kQuadCube = R"(# a unit cube of quads, no normals
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
)";

TEST(ParseObj, TriangulatesQuadsAndComputesOutwardNormals) {
  const LoadedObj obj = parse_obj(kQuadCube, "cube.obj");
  EXPECT_EQ(obj.stats.vertices_read, 8u);
  EXPECT_EQ(obj.stats.faces_read, 6u);
  EXPECT_EQ(obj.stats.polygons_triangulated, 6u);
  EXPECT_EQ(obj.mesh.triangle_count(), 12u);
  expect_unit_normals(obj.mesh);
  const glm::vec3 centre(0.5f);
  for (std::size_t i = 0; i < obj.mesh.vertex_count(); ++i) {
    EXPECT_GT(glm::dot(obj.mesh.normals[i], obj.mesh.positions[i] - centre), 0.0f);
  }
  float area = 0.0f;
  for (std::size_t t = 0; t < obj.mesh.triangle_count(); ++t) area += triangle_area(obj.mesh, t);
  EXPECT_FLOAT_EQ(area, 6.0f);
  EXPECT_EQ(obj.mesh.bounds.min, glm::vec3(0.0f));
  EXPECT_EQ(obj.mesh.bounds.max, glm::vec3(1.0f));
}

TEST(ParseObj, EarClipsNonConvexPolygonsKeepingTheirWinding) {
  // An arrow head listed from its left barb: a fan from there would cover the notch at
  // vertex 1, which lies outside the polygon, with a triangle of the wrong winding.
  const LoadedObj obj = parse_obj(R"(
v 0 1 0
v -2 -1 0
v 0 3 0
v 2 -1 0
f 2 3 4 1
)",
                                  "arrow.obj");
  ASSERT_EQ(obj.mesh.triangle_count(), 2u);
  float area = 0.0f;
  for (std::size_t t = 0; t < obj.mesh.triangle_count(); ++t) {
    const glm::vec3 a = obj.mesh.positions[obj.mesh.indices[3 * t]];
    const glm::vec3 b = obj.mesh.positions[obj.mesh.indices[3 * t + 1]];
    const glm::vec3 c = obj.mesh.positions[obj.mesh.indices[3 * t + 2]];
    EXPECT_LT(glm::cross(b - a, c - a).z, 0.0f) << "the polygon is clockwise seen from +z";
    area += triangle_area(obj.mesh, t);
  }
  // Shoelace area of the arrow: 4.
  EXPECT_FLOAT_EQ(area, 4.0f);
}

TEST(ParseObj, MergesDuplicatesDropsDegeneratesAndRemovesUnreferencedVertices) {
  const LoadedObj obj = parse_obj(R"(
v 0 0 0
v 1 0 0
v 0 1 0
v 1 0 0
v 0 1 0
v 1 1 0.5
v 2 0 0
v 100 100 100
f 1 2 3
f 4 6 5
f 1 1 2
f 1 2 7
)",
                                  "messy.obj");
  EXPECT_EQ(obj.stats.vertices_read, 8u);
  EXPECT_EQ(obj.stats.duplicate_vertices_merged, 2u);      // vertices 4 and 5
  EXPECT_EQ(obj.stats.degenerate_triangles_dropped, 2u);   // a repeated and a collinear one
  EXPECT_EQ(obj.stats.unreferenced_vertices_removed, 2u);  // 7 (only in the collinear) and 8
  EXPECT_EQ(obj.mesh.vertex_count(), 4u);
  EXPECT_EQ(obj.mesh.triangle_count(), 2u);
  EXPECT_EQ(obj.mesh.bounds.max, glm::vec3(1.0f, 1.0f, 0.5f));
  expect_unit_normals(obj.mesh);
  // The merged seam is smooth: the shared edge's vertices average both triangles' normals.
  const glm::vec3 n = obj.mesh.normals[1];
  EXPECT_GT(n.z, 0.0f);
  EXPECT_LT(n.z, 1.0f);
}

TEST(ParseObj, AcceptsRelativeIndicesAndTextureNormalIndices) {
  const LoadedObj obj = parse_obj(R"(
v 0 0 0
v 1 0 0
v 0 1 0
vt 0 0
vn 0 0 -1
f -3/1/1 -2/1/1 -1/1/1
)",
                                  "relative.obj");
  ASSERT_EQ(obj.mesh.triangle_count(), 1u);
  // File normals are ignored: the winding decides.
  EXPECT_EQ(obj.mesh.normals[0], glm::vec3(0, 0, 1));
}

TEST(ParseObj, NormalizesToTheUnitBoxWhenAsked) {
  std::string text = "v 10 20 30\nv 14 20 30\nv 10 22 30\nv 10 20 31\n";
  text += "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const LoadedObj obj = parse_obj(text, "off-centre.obj", {.normalize = true});
  EXPECT_EQ(obj.mesh.bounds.min, glm::vec3(-1.0f, -0.5f, -0.25f));
  EXPECT_EQ(obj.mesh.bounds.max, glm::vec3(1.0f, 0.5f, 0.25f));
  const LoadedObj raw = parse_obj(text, "off-centre.obj");
  EXPECT_EQ(raw.mesh.bounds.min, glm::vec3(10.0f, 20.0f, 30.0f));
}

TEST(ParseObj, SkipsAByteOrderMarkAndCommentsWhereverTheyStart) {
  const std::string plain = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 3 0\nf 1 2 3\nf 1 3 4\n";
  const LoadedObj reference = parse_obj(plain, "square.obj");
  ASSERT_EQ(reference.mesh.triangle_count(), 2u);
  // A mark before the first vertex would otherwise hide it and shift every index after it.
  const LoadedObj marked = parse_obj("\xEF\xBB\xBF" + plain, "bom.obj");
  EXPECT_EQ(marked.mesh.positions, reference.mesh.positions);
  EXPECT_EQ(marked.mesh.indices, reference.mesh.indices);
  const LoadedObj commented = parse_obj(
      "v -1 -1 0 # corner\nv 1 -1 0#no blank\nv 1 1 0\nv -1 1 0\nv 0 3 0\n"
      "f 1 2 3 # first\nf 1 3 4\t#second\n# f 1 2 5\n",
      "commented.obj");
  EXPECT_EQ(commented.mesh.positions, reference.mesh.positions);
  EXPECT_EQ(commented.mesh.indices, reference.mesh.indices);
}

TEST(ParseObj, JoinsLinesEndingInABackslash) {
  const LoadedObj reference =
      parse_obj("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n", "square.obj");
  const LoadedObj continued =
      parse_obj("v -1 -1 \\\n 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 \\\n3 \\\r\n4\n", "cont.obj");
  EXPECT_EQ(continued.mesh.positions, reference.mesh.positions);
  EXPECT_EQ(continued.mesh.indices, reference.mesh.indices);
}

TEST(ParseObj, AFaceWithoutVerticesIsNoFace) {
  // Not counted either: the faces after it keep their numbers in messages.
  const LoadedObj obj = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf\nf # empty\nf 1 2 3\n", "f.obj");
  EXPECT_EQ(obj.stats.faces_read, 1u);
  EXPECT_EQ(obj.mesh.triangle_count(), 1u);
  EXPECT_THAT(obj_error_of("v 0 0 0\nf\nf 1 2 3\n").what(), HasSubstr("line 3: face 1"));
}

TEST(ParseObj, AVertexWithoutNumbersStillCountsInTheIndices) {
  // Unused, it is ignored; faces after it still find vertices 2 to 5 where they were written.
  const LoadedObj obj =
      parse_obj("v\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 2 3 4\nf 2 4 5\n", "bare.obj");
  EXPECT_EQ(obj.mesh.triangle_count(), 2u);
  EXPECT_EQ(obj.mesh.bounds.min, glm::vec3(-1.0f, -1.0f, 0.0f));
  EXPECT_EQ(obj.mesh.bounds.max, glm::vec3(1.0f, 1.0f, 0.0f));
  // Used, the face is refused naming the vertex's line.
  EXPECT_THAT(obj_error_of("v\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").what(), HasSubstr("line 1"));
}

TEST(ParseObjErrors, NameTheFileAndTheProblem) {
  const ObjError range = obj_error_of("v 0 0 0\nv 1 0 0\nf 1 2 3\n", "two.obj");
  EXPECT_EQ(range.file(), "two.obj");
  EXPECT_THAT(range.what(), AllOf(HasSubstr("two.obj"), HasSubstr("face 1"), HasSubstr("vertex 3"),
                                  HasSubstr("only 2 vertices")));

  EXPECT_THAT(obj_error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n").what(),
              HasSubstr("uses relative index -4, but only 3 vertices are defined before it: at "
                        "least -3"));
  EXPECT_THAT(obj_error_of("f -1 -2 -3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").what(),
              HasSubstr("uses relative index -1, but no vertex is defined before it"));
  EXPECT_THAT(obj_error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n").what(),
              AllOf(HasSubstr("bad.obj"), HasSubstr("line 4")));
  EXPECT_THAT(obj_error_of("v 0 0 0\nv 1 0 0\n").what(), HasSubstr("no faces"));
  EXPECT_THAT(obj_error_of("not an obj file at all\n").what(), HasSubstr("no faces"));
  EXPECT_THAT(obj_error_of("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").what(), HasSubstr("degenerate"));
  EXPECT_THAT(obj_error_of("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2\nf 3\n").what(),
              AllOf(HasSubstr("line 4"), HasSubstr("every face has fewer than 3 vertices")));
}

TEST(LoadObj, MalformedFileGivesAClearError) {
  const TempFile file("malformed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 2 3 9\n");
  try {
    (void)load_obj(file.path());
    FAIL() << "expected an ObjError";
  } catch (const ObjError& e) {
    EXPECT_EQ(e.file(), file.path().string());
    EXPECT_THAT(e.what(), AllOf(HasSubstr(file.path().string()), HasSubstr("face 2"),
                                HasSubstr("vertex 9"), HasSubstr("only 3 vertices")));
  }
}

TEST(LoadObj, MissingFileOrDirectoryIsNamed) {
  EXPECT_THAT([] { (void)load_obj("/nonexistent/soltex/model.obj"); },
              ::testing::ThrowsMessage<ObjError>(
                  AllOf(HasSubstr("/nonexistent/soltex/model.obj"), HasSubstr("cannot open"))));
  EXPECT_THAT([] { (void)load_obj(std::filesystem::temp_directory_path()); },
              ::testing::ThrowsMessage<ObjError>(HasSubstr("is a directory")));
}

TEST(LoadObj, ReadsAFileLikeTheString) {
  const TempFile file("cube.obj", kQuadCube);
  const LoadedObj obj = load_obj(file.path());
  EXPECT_EQ(obj.mesh.triangle_count(), 12u);
}

// An OBJ file of the built-in sphere moved by `offset`, written with every digit a double has.
std::string sphere_obj(const glm::dvec3& offset) {
  const Mesh sphere = make_mesh(SphereShape{});
  std::string text;
  char line[128];
  for (const glm::vec3& p : sphere.positions) {
    const glm::dvec3 q = glm::dvec3(p) + offset;
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", q.x, q.y, q.z);
    text += line;
  }
  for (std::size_t t = 0; t < sphere.triangle_count(); ++t) {
    std::snprintf(line, sizeof line, "f %u %u %u\n", sphere.indices[3 * t] + 1,
                  sphere.indices[3 * t + 1] + 1, sphere.indices[3 * t + 2] + 1);
    text += line;
  }
  return text;
}

// Coordinates are read and normalised in double, so a model far from the origin lands on the
// same object-space mesh as the same model at the origin (in float, 1e9 + 0.01 == 1e9).
TEST(ParseObjFarFromTheOrigin, LoadsTheSameMeshAsAtTheOrigin) {
  const LoadedObj near = parse_obj(sphere_obj(glm::dvec3(0.0)), "near.obj", {.normalize = true});
  for (const glm::dvec3 offset :
       {glm::dvec3(1e6, -1e6, 1e6), glm::dvec3(1e9, 1e9, -1e9), glm::dvec3(-1e9, 0.0, 3e8)}) {
    SCOPED_TRACE(offset.x);
    const LoadedObj far = parse_obj(sphere_obj(offset), "far.obj", {.normalize = true});
    EXPECT_EQ(far.stats.degenerate_triangles_dropped, near.stats.degenerate_triangles_dropped);
    ASSERT_EQ(far.mesh.vertex_count(), near.mesh.vertex_count());
    ASSERT_EQ(far.mesh.indices, near.mesh.indices);
    float worst = 0.0f;
    for (std::size_t i = 0; i < near.mesh.vertex_count(); ++i) {
      const glm::vec3 d = glm::abs(far.mesh.positions[i] - near.mesh.positions[i]);
      worst = std::max({worst, d.x, d.y, d.z});
    }
    // A double resolves 1.2e-7 at 1e9: about one float step on the unit sphere.
    EXPECT_LE(worst, offset.x == 1e6 ? 2.4e-7f : 5e-7f);
  }
}

TEST(ParseObjFarFromTheOrigin, WithoutNormalizingFloatRangeIsTheBound) {
  EXPECT_THAT(obj_error_of("v 1e39 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n").what(),
              AllOf(HasSubstr("beyond float range"), HasSubstr("normalize")));
  const LoadedObj obj =
      parse_obj("v 1e39 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n", "huge.obj", {.normalize = true});
  EXPECT_EQ(obj.mesh.bounds.max.x, 1.0f);
}

TEST(ParseObjErrors, AFaceUsingANonFiniteVertexNamesBothLines) {
  for (const char* vertex : {"v nan 0 0", "v 0 inf 0", "v 0 0 -Infinity", "v 1e400 0 0",
                             "v 1 abc 0", "v 1.5x 0 0", "v 1 2"}) {
    SCOPED_TRACE(vertex);
    const std::string text = std::string("v 0 0 0\n") + vertex + "\nv 0 1 0\n# the face\nf 1 2 3\n";
    const ObjError error = obj_error_of(text, "nan.obj");
    EXPECT_THAT(error.what(),
                AllOf(HasSubstr("nan.obj"), HasSubstr("line 5: face 1"), HasSubstr("vertex 2"),
                      HasSubstr("line 2 reads"), HasSubstr(vertex)));
  }
}

TEST(ParseObj, IgnoresANonFiniteVertexNoFaceUses) {
  const LoadedObj obj = parse_obj("v 0 0 0\nv nan nan nan\nv 1 0 0\nv 0 1 0\nf 1 3 4\n", "x.obj");
  EXPECT_EQ(obj.stats.vertices_read, 4u);
  EXPECT_EQ(obj.stats.unreferenced_vertices_removed, 1u);
  EXPECT_EQ(obj.mesh.triangle_count(), 1u);
}

TEST(ParseObj, ReadsCoordinatesCorrectlyRoundedWithSignsAndExponents) {
  const LoadedObj obj =
      parse_obj("v +0.1 -2.5e-1 1E2\nv 0.3 0 0\r\nv 0 0.3 0\rf 1 2 3/1/1\n", "x.obj");
  ASSERT_EQ(obj.mesh.vertex_count(), 3u);
  EXPECT_EQ(obj.mesh.bounds.min, glm::vec3(0.0f, -0.25f, 0.0f));
  EXPECT_EQ(obj.mesh.bounds.max, glm::vec3(0.3f, 0.3f, 100.0f));
}

// A star of `points` tips: every other vertex is reflex, so a fan from vertex 0 covers area
// outside the polygon with triangles of the wrong winding.
std::string star_obj(std::size_t points, double inner = 0.3) {
  std::string text;
  char line[96];
  const double pi = std::acos(-1.0);
  for (std::size_t i = 0; i < 2 * points; ++i) {
    const double angle = pi * static_cast<double>(i) / static_cast<double>(points);
    const double r = i % 2 == 0 ? 1.0 : inner;
    std::snprintf(line, sizeof line, "v %.17g %.17g 0\n", r * std::cos(angle), r * std::sin(angle));
    text += line;
  }
  text += "f";
  for (std::size_t i = 0; i < 2 * points; ++i) {
    text += ' ';
    text += std::to_string(i + 1);
  }
  return text + "\n";
}

double shoelace(const std::vector<glm::dvec2>& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec2 &a = polygon[i], &b = polygon[(i + 1) % polygon.size()];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * twice;
}

void expect_covers_exactly(const LoadedObj& obj, double area, std::size_t corners) {
  EXPECT_EQ(obj.mesh.triangle_count(), corners - 2);
  double sum = 0.0;
  for (std::size_t t = 0; t < obj.mesh.triangle_count(); ++t) {
    const glm::dvec3 a(obj.mesh.positions[obj.mesh.indices[3 * t]]);
    const glm::dvec3 b(obj.mesh.positions[obj.mesh.indices[3 * t + 1]]);
    const glm::dvec3 c(obj.mesh.positions[obj.mesh.indices[3 * t + 2]]);
    const double z = glm::cross(b - a, c - a).z;
    ASSERT_GT(z, 0.0) << "triangle " << t << " is flipped: it covers area outside the polygon";
    sum += 0.5 * z;
  }
  // Triangles all of the polygon's winding whose areas add up to the polygon's cover it
  // without overlap.
  EXPECT_NEAR(sum, area, 1e-5 * area);
}

TEST(ParseObjPolygons, EarClipsNonConvexPolygonsOfAnySize) {
  for (const std::size_t points : {33u, 40u, 150u, 2000u}) {
    SCOPED_TRACE(points);
    const std::string text = star_obj(points);
    const LoadedObj obj = parse_obj(text, "star.obj");
    std::vector<glm::dvec2> outline;
    for (const glm::vec3& p : obj.mesh.positions) outline.emplace_back(p.x, p.y);
    EXPECT_EQ(obj.stats.polygons_triangulated, 1u);
    expect_covers_exactly(obj, shoelace(outline), 2 * points);
  }
}

// A comb: a (2 teeth - 1) x 1 base with teeth of 1 x 9 on it, so half the corners are reflex
// and ears are few; listed counter-clockwise seen from +z. Integer coordinates keep every
// triangle exact in float, however many there are.
std::string comb_obj(int teeth) {
  std::string text = "v 0 0 0\nv " + std::to_string(2 * teeth - 1) + " 0 0\n";
  const auto vertex = [&](int x, int y) {
    text += "v " + std::to_string(x) + " " + std::to_string(y) + " 0\n";
  };
  for (int i = teeth - 1; i >= 0; --i) {
    vertex(2 * i + 1, 10);
    vertex(2 * i, 10);
    if (i > 0) {
      vertex(2 * i, 1);
      vertex(2 * i - 1, 1);
    }
  }
  text += "f";
  for (int i = 1; i <= 4 * teeth; ++i) {
    text += ' ';
    text += std::to_string(i);
  }
  return text + "\n";
}

double comb_area(int teeth) {
  return (2 * teeth - 1) * 1.0 + teeth * 9.0;
}

TEST(ParseObjPolygons, EarClipsACombOfManyTeeth) {
  const LoadedObj obj = parse_obj(comb_obj(100), "comb.obj");
  expect_covers_exactly(obj, comb_area(100), 400);
}

// More than 255 vertices in one face: a library that counts them in a byte would hand the
// rest to the next face.
TEST(ParseObjPolygons, APolygonOfThousandsOfVerticesLeavesTheNextFaceIntact) {
  std::string text = star_obj(300);
  text += "v 5 5 1\nv 6 5 1\nv 5 6 1\nf -3 -2 -1\n";
  const LoadedObj obj = parse_obj(text, "two.obj");
  EXPECT_EQ(obj.stats.faces_read, 2u);
  EXPECT_EQ(obj.mesh.triangle_count(), 598u + 1u);
}

TEST(ParseObjPolygons, LargestFaceLoadsAndOneMoreIsRefusedWithTheBound) {
  const int teeth = static_cast<int>(kMaxFaceVertices / 4);
  expect_covers_exactly(parse_obj(comb_obj(teeth), "largest.obj"), comb_area(teeth),
                        kMaxFaceVertices);
  std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
  for (std::size_t i = 0; i <= kMaxFaceVertices; ++i) {
    text += ' ';
    text += std::to_string(1 + i % 3);
  }
  EXPECT_THAT(
      obj_error_of(text + "\n", "huge.obj").what(),
      AllOf(HasSubstr("huge.obj"), HasSubstr("line 4: face 1"), HasSubstr("more than 16384")));
}

// An L (a 2 x 2 square less its 1 x 1 top right), its reflex corner at (1, 1), every x and y
// times `scale`, in the plane z = `z`.
std::string l_shape_obj(double scale, double z = 0.0) {
  std::string text;
  for (const auto& [x, y] : {std::pair{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}) {
    char line[128];
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", x * scale, y * scale, z);
    text += line;
  }
  return text + "f 1 2 3 4 5 6\n";
}

TEST(ParseObjPolygons, AConcavePolygonKeepsItsShapeAtAnyScale) {
  // Near DBL_MAX the corners' differences overflow, and near 1e155 their cross products: the
  // reflex corner must still be seen, or the notch would be filled. Below 1e-162 the cross
  // products underflow: the triangles must not be taken for ones of zero area.
  const LoadedObj unit = parse_obj(l_shape_obj(1.0), "l.obj", {.normalize = true});
  double area = 0.0;
  for (std::size_t t = 0; t < unit.mesh.triangle_count(); ++t) area += triangle_area(unit.mesh, t);
  for (const double scale : {1e-300, 1e-200, 1e-150, 1e155, 1e300, 8e307}) {
    SCOPED_TRACE(scale);
    const LoadedObj obj = parse_obj(l_shape_obj(scale), "l.obj", {.normalize = true});
    expect_covers_exactly(obj, area, 6);
  }
  // Small and far: its size, not its distance from the origin, must set the scale.
  const LoadedObj far = parse_obj(l_shape_obj(1e-100, 1e100), "far.obj", {.normalize = true});
  expect_covers_exactly(far, area, 6);
}

TEST(ParseObjPolygons, StraightAndDoubledBackCornersAddNoTriangles) {
  // A square with a midpoint on each side and a repeated corner.
  const LoadedObj obj = parse_obj(R"(
v 0 0 0
v 1 0 0
v 2 0 0
v 2 1 0
v 2 2 0
v 1 2 0
v 0 2 0
v 0 1 0
f 1 2 3 3 4 5 6 7 8
)",
                                  "square.obj");
  float area = 0.0f;
  for (std::size_t t = 0; t < obj.mesh.triangle_count(); ++t) area += triangle_area(obj.mesh, t);
  EXPECT_FLOAT_EQ(area, 4.0f);
}

// The real test meshes beside the checkout (../shared/models). A clone without them skips
// these tests. Every face in these files is a triangle and none is degenerate, so the
// triangle counts are exactly the README's. What the cleanup finds, as measured: the bunny
// lists 1,113 vertices that no face uses (35,947 read), and the teapot repeats 403
// positions along the seams of its patches; spot and the rocker arm are clean.
struct SharedModel {
  const char* file;
  std::size_t triangles;  // as in the models' README
  std::size_t duplicate_vertices;
  std::size_t unreferenced_vertices;
};

class SharedModels : public ::testing::TestWithParam<SharedModel> {};

TEST_P(SharedModels, LoadWithNormalsAndNormalizeToTheUnitBox) {
  const std::filesystem::path path =
      std::filesystem::path(SOLTEX_SHARED_MODELS_DIR) / GetParam().file;
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << path << " is absent (the shared test models sit beside the checkout)";
  }
  const LoadedObj obj = load_obj(path, {.normalize = true});
  const ObjLoadStats& stats = obj.stats;
  EXPECT_EQ(stats.faces_read, GetParam().triangles);
  EXPECT_EQ(stats.polygons_triangulated, 0u);
  EXPECT_EQ(stats.degenerate_triangles_dropped, 0u);
  EXPECT_EQ(obj.mesh.triangle_count(), GetParam().triangles);
  EXPECT_EQ(stats.duplicate_vertices_merged, GetParam().duplicate_vertices);
  EXPECT_EQ(stats.unreferenced_vertices_removed, GetParam().unreferenced_vertices);
  EXPECT_EQ(obj.mesh.vertex_count(), stats.vertices_read - stats.duplicate_vertices_merged -
                                         stats.unreferenced_vertices_removed +
                                         stats.vertices_split_at_creases);
  expect_unit_normals(obj.mesh);
  const glm::vec3 size = obj.mesh.bounds.size();
  EXPECT_FLOAT_EQ(std::max({size.x, size.y, size.z}), 2.0f);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(obj.mesh.bounds.min[axis], -obj.mesh.bounds.max[axis], 1e-6f);
    EXPECT_GE(obj.mesh.bounds.min[axis], -1.0f);
    EXPECT_LE(obj.mesh.bounds.max[axis], 1.0f);
  }
}

INSTANTIATE_TEST_SUITE_P(Readme, SharedModels,
                         ::testing::Values(SharedModel{"stanford-bunny.obj", 69451, 0, 1113},
                                           SharedModel{"teapot.obj", 6320, 403, 0},
                                           SharedModel{"spot.obj", 5856, 0, 0},
                                           SharedModel{"rocker-arm.obj", 20088, 0, 0}),
                         [](const ::testing::TestParamInfo<SharedModel>& info) {
                           std::string name = info.param.file;
                           name = name.substr(0, name.find('.'));
                           std::erase(name, '-');
                           return name;
                         });

}  // namespace
}  // namespace soltex
