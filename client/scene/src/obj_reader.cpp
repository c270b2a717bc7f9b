#include "obj_reader.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "soltex/scene/obj_loader.h"

namespace soltex {
namespace {

bool is_blank(char c) {
  return c == ' ' || c == '\t';
}

// The next blank-separated token of `line`, advancing past it; empty at the end.
std::string_view next_token(std::string_view& line) {
  std::size_t begin = 0;
  while (begin < line.size() && is_blank(line[begin])) ++begin;
  std::size_t end = begin;
  while (end < line.size() && !is_blank(line[end])) ++end;
  const std::string_view token = line.substr(begin, end - begin);
  line.remove_prefix(end);
  return token;
}

// from_chars reads no leading '+', which some exporters write.
std::string_view without_plus(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  return token;
}

// A whole token as a double; NaN when it is not one (partly numeric tokens included).
double read_coordinate(std::string_view token) {
  token = without_plus(token);
  double value = std::numeric_limits<double>::quiet_NaN();
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  // Out of range, from_chars leaves the value alone; strtod tells overflow (HUGE_VAL, not
  // finite) from underflow (0 or a subnormal, a fine coordinate).
  if (error == std::errc::result_out_of_range)
    return std::strtod(std::string(token).c_str(), nullptr);
  if (error != std::errc() || end != token.data() + token.size()) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return value;
}

std::string shortened(std::string_view line) {
  constexpr std::size_t kMaxQuoted = 60;
  return line.size() <= kMaxQuoted ? std::string(line)
                                   : std::string(line.substr(0, kMaxQuoted)) + "...";
}

void read_vertex(std::string_view statement, std::string_view rest, std::size_t line_number,
                 ObjText& out) {
  glm::dvec3 p;
  bool finite = true;
  for (int axis = 0; axis < 3; ++axis) {
    p[axis] = read_coordinate(next_token(rest));  // a missing one reads as NaN
    finite = finite && std::isfinite(p[axis]);
  }
  // Further numbers (w, or a vertex colour) are ignored.
  if (!finite) {
    p = glm::dvec3(std::numeric_limits<double>::quiet_NaN());
    out.bad_vertices.push_back(static_cast<uint32_t>(out.positions.size()));
    out.bad_vertex_lines.push_back(line_number);
    out.bad_vertex_texts.push_back(shortened(statement));
  }
  out.positions.push_back(p);
}

void read_face(std::string_view rest, std::size_t line_number, const std::string& name,
               ObjText& out) {
  // Built only for a message: a large file has millions of faces.
  const auto where = [&] {
    return "line " + std::to_string(line_number) + ": face " +
           std::to_string(out.face_sizes.size() + 1);
  };
  const int64_t defined = static_cast<int64_t>(out.positions.size());
  uint32_t size = 0;
  for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
    // "v", "v/vt", "v//vn" or "v/vt/vn": only the position index matters here.
    const std::string_view index_text = without_plus(token.substr(0, token.find('/')));
    int64_t index = 0;
    const auto [end, error] =
        std::from_chars(index_text.data(), index_text.data() + index_text.size(), index);
    if (error == std::errc::result_out_of_range) {
      throw ObjError(name, where() + ": vertex index " + shortened(token) +
                               " is past 2^32, the most a mesh can index");
    }
    if (error != std::errc() || end != index_text.data() + index_text.size()) {
      throw ObjError(name, where() + ": \"" + shortened(token) + "\" is not a vertex index");
    }
    if (index == 0) throw ObjError(name, where() + ": vertex index 0 (OBJ indices start at 1)");
    // Negative indices count back from the last vertex defined so far.
    const int64_t absolute = index > 0 ? index - 1 : defined + index;
    if (absolute < 0) {
      const std::string bound = defined == 0 ? "no vertex is defined before it"
                                             : "only " + std::to_string(defined) +
                                                   " vertices are defined before it: at least -" +
                                                   std::to_string(defined);
      throw ObjError(name,
                     where() + " uses relative index " + std::to_string(index) + ", but " + bound);
    }
    if (absolute > std::numeric_limits<uint32_t>::max()) {
      throw ObjError(name, where() + ": vertex index " + std::to_string(index) +
                               " is past 2^32, the most a mesh can index");
    }
    if (++size > kMaxFaceVertices) {
      throw ObjError(name, where() + " has more than " + std::to_string(kMaxFaceVertices) +
                               " vertices, the most one face may have");
    }
    out.corners.push_back(static_cast<uint32_t>(absolute));
  }
  out.face_sizes.push_back(size);
  out.face_lines.push_back(line_number);
}

// The next line of `text`, advancing past it: lines end in "\n", "\r\n" or a lone "\r".
std::string_view next_line(std::string_view& text) {
  const std::size_t end = text.find_first_of("\r\n");
  const std::string_view line = text.substr(0, end);
  std::size_t consumed = end == std::string_view::npos ? text.size() : end + 1;
  if (end != std::string_view::npos && text[end] == '\r' && end + 1 < text.size() &&
      text[end + 1] == '\n') {
    ++consumed;
  }
  text.remove_prefix(consumed);
  return line;
}

// What a line states: without its comment ('#' to the end) and the blanks around the rest.
std::string_view statement_of(std::string_view line) {
  line = line.substr(0, line.find('#'));
  while (!line.empty() && is_blank(line.front())) line.remove_prefix(1);
  while (!line.empty() && is_blank(line.back())) line.remove_suffix(1);
  return line;
}

void read_statement(std::string_view statement, std::size_t line_number, const std::string& name,
                    ObjText& out) {
  std::string_view rest = statement;
  const std::string_view keyword = next_token(rest);
  // A "v" with too few numbers is still a vertex: later indices keep counting it, and a face
  // that uses it is refused.
  if (keyword == "v") {
    read_vertex(statement, rest, line_number, out);
  } else if (keyword == "f") {
    std::string_view probe = rest;
    if (next_token(probe).empty()) return;  // an "f" with no vertex is no face
    read_face(rest, line_number, name, out);
  }
}

}  // namespace

ObjText read_obj_text(std::string_view text, const std::string& name_for_errors) {
  ObjText out;
  // A byte-order mark, which some Windows tools write: the first statement starts after it.
  constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
  if (text.starts_with(kUtf8Bom)) text.remove_prefix(kUtf8Bom.size());
  std::size_t line_number = 0;
  std::string joined;  // a statement continued over lines, each but the last ending in '\\'
  while (!text.empty()) {
    std::string_view statement = statement_of(next_line(text));
    const std::size_t first_line = ++line_number;
    if (statement.ends_with('\\')) {
      joined.assign(statement.substr(0, statement.size() - 1));
      bool continued = true;
      while (continued && !text.empty()) {
        std::string_view more = statement_of(next_line(text));
        ++line_number;
        continued = more.ends_with('\\');
        if (continued) more.remove_suffix(1);
        joined.append(" ").append(more);
      }
      statement = statement_of(joined);
    }
    read_statement(statement, first_line, name_for_errors, out);
  }
  return out;
}

}  // namespace soltex
