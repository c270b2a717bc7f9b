#include "graph_proto.h"

#include <string>

#include "soltex/common/overloaded.h"
#include "soltex/common/quoted_text.h"
#include "soltex/common/spec_error.h"

namespace soltex {
namespace {

graph::InputValue input_from(const v1::GraphInput& m, const std::string& field) {
  switch (m.value_case()) {
    case v1::GraphInput::kNumber:
      return m.number();
    case v1::GraphInput::kVector:
      return glm::dvec3(m.vector().x(), m.vector().y(), m.vector().z());
    case v1::GraphInput::kNode:
      return graph::NodeRef{m.node()};
    case v1::GraphInput::kChoice:
      return m.choice();
    case v1::GraphInput::kKeys: {
      graph::RampKeys keys;
      for (const auto& key : m.keys().keys()) {
        keys.push_back({key.position(), {key.colour().r(), key.colour().g(), key.colour().b()}});
      }
      return keys;
    }
    case v1::GraphInput::VALUE_NOT_SET:
      break;
  }
  throw SpecError(field, "unset", "one of number, vector, node, choice, keys must be set");
}

Channel channel_from(v1::Channel channel, const std::string& field) {
  switch (channel) {
    case v1::CHANNEL_COLOUR:
      return Channel::colour;
    case v1::CHANNEL_OPACITY:
      return Channel::opacity;
    case v1::CHANNEL_SPECULAR:
      return Channel::specular;
    default:
      throw SpecError(field, std::to_string(channel),
                      "must be CHANNEL_COLOUR, CHANNEL_OPACITY or CHANNEL_SPECULAR");
  }
}

}  // namespace

graph::TextureGraph graph_from_proto(const v1::Graph& m) {
  graph::TextureGraph g;
  g.nodes.reserve(static_cast<std::size_t>(m.nodes_size()));
  for (const auto& node : m.nodes()) {
    graph::Node n{node.name(), node.category(), node.type(), {}};
    for (const auto& input : node.inputs()) {
      n.inputs.push_back(
          {input.name(), input_from(input, "graph.nodes[" + escaped_text(node.name()) + "]." +
                                               escaped_text(input.name()))});
    }
    g.nodes.push_back(std::move(n));
  }
  for (int i = 0; i < m.outputs_size(); ++i) {
    const auto& out = m.outputs(i);
    g.outputs.push_back(
        {channel_from(out.channel(), "graph.outputs[" + std::to_string(i) + "].channel"),
         out.node()});
  }
  return g;
}

v1::Graph graph_to_proto(const graph::TextureGraph& graph) {
  v1::Graph m;
  for (const graph::Node& node : graph.nodes) {
    auto* n = m.add_nodes();
    n->set_name(node.name);
    n->set_category(node.category);
    n->set_type(node.type);
    for (const graph::NodeInput& input : node.inputs) {
      auto* in = n->add_inputs();
      in->set_name(input.name);
      std::visit(Overloaded{
                     [&](double v) { in->set_number(v); },
                     [&](const glm::dvec3& v) {
                       in->mutable_vector()->set_x(v.x);
                       in->mutable_vector()->set_y(v.y);
                       in->mutable_vector()->set_z(v.z);
                     },
                     [&](const graph::NodeRef& r) { in->set_node(r.node); },
                     [&](const std::string& s) { in->set_choice(s); },
                     [&](const graph::RampKeys& keys) {
                       for (const RampKey& key : keys) {
                         auto* k = in->mutable_keys()->add_keys();
                         k->set_position(key.position);
                         k->mutable_colour()->set_r(key.colour.r);
                         k->mutable_colour()->set_g(key.colour.g);
                         k->mutable_colour()->set_b(key.colour.b);
                       }
                     },
                 },
                 input.value);
    }
  }
  for (const graph::GraphOutput& out : graph.outputs) {
    auto* o = m.add_outputs();
    o->set_channel(out.channel == Channel::colour    ? v1::CHANNEL_COLOUR
                   : out.channel == Channel::opacity ? v1::CHANNEL_OPACITY
                                                     : v1::CHANNEL_SPECULAR);
    o->set_node(out.node);
  }
  return m;
}

}  // namespace soltex
