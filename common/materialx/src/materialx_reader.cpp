#include "soltex/materialx/materialx_reader.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <map>
#include <pugixml.hpp>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "soltex/common/quoted_text.h"
#include "soltex/common/spec_error.h"

namespace soltex::materialx {
namespace {

// Standard nodes the node catalogue has under the same name and with the same meaning.
constexpr std::array kSupported = {
    "position", "constant", "add",        "subtract",    "multiply",     "divide",
    "modulo",   "power",    "min",        "max",         "absval",       "floor",
    "ceil",     "sin",      "cos",        "sqrt",        "clamp",        "smoothstep",
    "remap",    "mix",      "dotproduct", "magnitude",   "extract",      "combine3",
    "convert",  "noise3d",  "fractal3d",  "cellnoise3d", "worleynoise3d"};

class Document {
 public:
  explicit Document(const MaterialxSource& source) : source_(source) {
    const pugi::xml_parse_result parsed =
        xml_.load_buffer(source.text.data(), source.text.size(), pugi::parse_default);
    if (!parsed) {
      fail(static_cast<std::ptrdiff_t>(parsed.offset),
           std::string("not XML: ") + parsed.description());
    }
  }

  [[noreturn]] void fail(std::ptrdiff_t offset, const std::string& problem) const {
    throw MaterialxError(source_.document + ":" + std::to_string(line_of(offset)) + ": " + problem);
  }
  int line_of(std::ptrdiff_t offset) const {
    const auto end =
        source_.text.begin() +
        std::clamp<std::ptrdiff_t>(offset, 0, static_cast<std::ptrdiff_t>(source_.text.size()));
    return 1 + static_cast<int>(std::count(source_.text.begin(), end, '\n'));
  }
  const pugi::xml_document& xml() const { return xml_; }
  const MaterialxSource& source() const { return source_; }

 private:
  const MaterialxSource& source_;
  pugi::xml_document xml_;
};

std::string node_words(const pugi::xml_node& node) {
  return "node " + quoted_text(node.attribute("name").value()) + " (" + escaped_text(node.name()) +
         ")";
}

// A value string's comma-separated numbers, decimal as MaterialX writes them (no hex, no
// empty item: "0.9, 0.2, 0.1," is a typo, not three numbers); empty when it is not that.
std::vector<double> numbers(const std::string& text) {
  std::vector<double> values;
  std::string item;
  std::istringstream stream(text + ",");  // the last item is then ended like the others
  while (std::getline(stream, item, ',')) {
    std::string_view view = item;
    while (!view.empty() && view.front() == ' ') view.remove_prefix(1);
    while (!view.empty() && view.back() == ' ') view.remove_suffix(1);
    double v = 0.0;
    const auto [end, error] = std::from_chars(view.data(), view.data() + view.size(), v);
    if (view.empty() || error != std::errc() || end != view.data() + view.size()) return {};
    values.push_back(v);
  }
  return values;
}

// The colour space a color3 value is written in: its own `colorspace`, else the nearest
// enclosing element's (node, nodegraph, document); empty when none says.
std::string colour_space_of(const pugi::xml_node& input) {
  for (pugi::xml_node at = input; at; at = at.parent()) {
    if (const auto space = at.attribute("colorspace")) return space.value();
  }
  return {};
}

// sRGB's transfer function undone (IEC 61966-2-1), per component.
glm::dvec3 linear_from_srgb(const glm::dvec3& c) {
  glm::dvec3 linear;
  for (int i = 0; i < 3; ++i) {
    linear[i] = c[i] <= 0.04045 ? c[i] / 12.92 : std::pow((c[i] + 0.055) / 1.055, 2.4);
  }
  return linear;
}

// A color3 value in the working space (linear Rec. 709): as written there, or from sRGB.
glm::dvec3 working_colour(const Document& doc, const pugi::xml_node& input,
                          const std::string& where, const glm::dvec3& value) {
  const std::string space = colour_space_of(input);
  if (space.empty() || space == "lin_rec709") return value;
  if (space == "srgb_texture") return linear_from_srgb(value);
  doc.fail(input.offset_debug(), where + ": colorspace " + quoted_text(space) +
                                     " is not supported (lin_rec709, the working space, or "
                                     "srgb_texture)");
}

// A connection whose input declares a type must name a node of that type.
void check_connected_type(const Document& doc, const pugi::xml_node& node,
                          const pugi::xml_node& input, const std::string& where) {
  const std::string declared = input.attribute("type").value();
  if (declared.empty()) return;
  const pugi::xml_node source =
      node.parent().find_child_by_attribute("name", input.attribute("nodename").value());
  const std::string actual = source.attribute("type").value();
  if (source && !actual.empty() && actual != declared) {
    doc.fail(input.offset_debug(), where + " is declared " + quoted_text(declared) + ", but node " +
                                       quoted_text(input.attribute("nodename").value()) + " is " +
                                       quoted_text(actual));
  }
}

graph::InputValue input_value(const Document& doc, const pugi::xml_node& node,
                              const pugi::xml_node& input) {
  const std::string where =
      node_words(node) + " input " + quoted_text(input.attribute("name").value());
  const auto offset = input.offset_debug();
  if (input.attribute("interfacename")) {
    doc.fail(offset, where + ": interface inputs are not supported; give a value or a nodename");
  }
  if (input.attribute("output")) {
    doc.fail(offset, where + ": outputs of multi-output nodes are not supported");
  }
  if (input.attribute("channels")) {
    doc.fail(offset, where + ": channel swizzles (channels=\"" +
                         escaped_text(input.attribute("channels").value()) +
                         "\") are not supported; use extract and combine3");
  }
  const auto value = input.attribute("value");
  if (const auto ref = input.attribute("nodename")) {
    if (value) doc.fail(offset, where + ": give a value or a nodename, not both");
    check_connected_type(doc, node, input, where);
    return graph::NodeRef{ref.value()};
  }
  if (!value) doc.fail(offset, where + ": needs a value or a nodename");
  const std::string type = input.attribute("type").value();
  const std::string text = value.value();
  constexpr std::string_view kInputTypes[] = {"",        "float",  "integer", "boolean",
                                              "vector3", "color3", "string"};
  if (std::find(std::begin(kInputTypes), std::end(kInputTypes), type) == std::end(kInputTypes)) {
    doc.fail(offset, where + ": type " + quoted_text(type) +
                         " is not supported (float, integer, boolean, vector3, color3, string)");
  }
  if (type == "boolean") {
    if (!graph::takes_boolean(node.name(), input.attribute("name").value())) {
      doc.fail(offset, where + ": takes a number, not a boolean");
    }
    if (text == "true") return 1.0;
    if (text == "false") return 0.0;
    doc.fail(offset, where + ": boolean " + quoted_text(text) + " must be true or false");
  }
  if (type == "string") return text;
  const std::vector<double> v = numbers(text);
  if (v.size() == 1 && (type == "float" || type == "integer" || type.empty())) return v[0];
  if (v.size() == 3 && type == "color3") {
    return working_colour(doc, input, where, glm::dvec3(v[0], v[1], v[2]));
  }
  if (v.size() == 3 && (type == "vector3" || type.empty())) return glm::dvec3(v[0], v[1], v[2]);
  doc.fail(offset, where + ": value " + quoted_text(text) + " is not a " +
                       (type.empty() ? std::string("number") : type));
}

graph::Node read_node(const Document& doc, const pugi::xml_node& node) {
  const std::string category = node.name();
  if (!is_supported_category(category)) {
    doc.fail(node.offset_debug(), node_words(node) +
                                      ": not a supported MaterialX node (docs/SCENES.md, "
                                      "\"MaterialX documents\", lists them)");
  }
  graph::Node out{node.attribute("name").value(), category, node.attribute("type").value(), {}};
  if (out.type == "vector3" || out.type == "color3" || out.type == "float") {
    // As written; compile() checks it against the node.
  } else {
    doc.fail(node.offset_debug(), node_words(node) + ": type " + quoted_text(out.type) +
                                      " is not supported (float, vector3, color3)");
  }
  for (const pugi::xml_node& input : node.children("input")) {
    out.inputs.push_back({input.attribute("name").value(), input_value(doc, node, input)});
  }
  // MaterialX's position has a space input; the texture space is the only one here.
  if (category == "position") out.inputs.clear();
  return out;
}

pugi::xml_node find_nodegraph(const Document& doc) {
  const pugi::xml_node root = doc.xml().child("materialx");
  if (!root) doc.fail(0, "no <materialx> element");
  const std::string& wanted = doc.source().nodegraph;
  const auto graph = root.find_child_by_attribute("nodegraph", "name", wanted.c_str());
  if (!graph) doc.fail(root.offset_debug(), "no nodegraph named " + quoted_text(wanted));
  // Which one was meant is not for the reader to guess.
  for (auto other = graph.next_sibling("nodegraph"); other;
       other = other.next_sibling("nodegraph")) {
    if (wanted == other.attribute("name").value()) {
      doc.fail(other.offset_debug(), "a second nodegraph named " + quoted_text(wanted) +
                                         " (the first is on line " +
                                         std::to_string(doc.line_of(graph.offset_debug())) + ")");
    }
  }
  return graph;
}

// Whether a nodegraph's child is one of its nodes (read_node() reads it), not its output or
// an editor's note.
bool is_graph_node(const pugi::xml_node& child) {
  const std::string name = child.name();
  return child.type() == pugi::node_element && name != "output" && name != "backdrop";
}

// The element a compile() error's field is about: "graph.nodes[NAME]..." the node of that
// name, "graph.nodes[I]..." (a name that is no use, such as one too long) the I-th node,
// "graph.outputs..." the output asked for; otherwise the nodegraph itself.
pugi::xml_node element_of_field(const pugi::xml_node& nodegraph, const std::string& field,
                                const std::string& output) {
  if (field.starts_with("graph.outputs")) {
    const auto out = nodegraph.find_child_by_attribute("output", "name", output.c_str());
    return out ? out : nodegraph;
  }
  const std::size_t open = field.find('['), close = field.find(']');
  if (!field.starts_with("graph.nodes[") || close == std::string::npos) return nodegraph;
  // The field shows the name as escaped_text() does; a name may hold ']' itself, so the
  // longest name the field starts with is the node's.
  pugi::xml_node named;
  std::size_t longest = 0;
  for (const pugi::xml_node& child : nodegraph.children()) {
    if (!is_graph_node(child)) continue;
    const std::string prefix = "graph.nodes[" + escaped_text(child.attribute("name").value()) + "]";
    if (field.starts_with(prefix) && prefix.size() > longest) {
      named = child;
      longest = prefix.size();
    }
  }
  if (named) return named;
  const std::string key = field.substr(open + 1, close - open - 1);
  std::size_t index = 0;
  for (const pugi::xml_node& child : nodegraph.children()) {
    if (!is_graph_node(child)) continue;
    if (key == std::to_string(index++)) return child;
  }
  return nodegraph;
}

}  // namespace

bool is_supported_category(const std::string& category) {
  return std::find(kSupported.begin(), kSupported.end(), category) != kSupported.end();
}

graph::TextureGraph read_nodegraph(const MaterialxSource& source) {
  const Document doc(source);
  const pugi::xml_node nodegraph = find_nodegraph(doc);
  graph::TextureGraph result;
  bool found = false;
  for (const pugi::xml_node& child : nodegraph.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string name = child.name();
    if (name == "output") {
      if (source.output == child.attribute("name").value()) {
        if (std::string(child.attribute("type").value()) != "color3") {
          doc.fail(child.offset_debug(),
                   "output " + quoted_text(source.output) + " must be color3");
        }
        if (!child.attribute("nodename")) {
          doc.fail(child.offset_debug(), "output " + quoted_text(source.output) +
                                             " needs a nodename: the node whose colour it is");
        }
        result.outputs.push_back({Channel::colour, child.attribute("nodename").value()});
        found = true;
      }
      continue;
    }
    if (!is_graph_node(child)) continue;  // a backdrop: a note for editors
    result.nodes.push_back(read_node(doc, child));
  }
  if (!found) {
    doc.fail(nodegraph.offset_debug(), "nodegraph " + quoted_text(source.nodegraph) +
                                           " has no output " + quoted_text(source.output));
  }
  return result;
}

std::shared_ptr<const graph::CompiledGraph> compile_nodegraph(const MaterialxSource& source) {
  graph::TextureGraph g = read_nodegraph(source);
  try {
    return graph::compile(std::move(g));
  } catch (const SpecError& e) {
    // Pointed at the line of the node or output the error is about.
    const Document doc(source);
    const pugi::xml_node nodegraph = find_nodegraph(doc);
    doc.fail(element_of_field(nodegraph, e.field(), source.output).offset_debug(), e.what());
  }
}

}  // namespace soltex::materialx
