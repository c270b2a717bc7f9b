#include <gtest/gtest.h>

#include "../graph/graph_builders.h"
#include "soltex/common/spec_error.h"
#include "soltex/common/texture_id.h"
#include "soltex/graph/compiled_graph.h"
#include "soltex/spec_proto/spec_from_proto.h"

namespace soltex {
namespace {

TextureSpec graph_spec(const graph::TextureGraph& g) {
  TextureSpec spec;
  spec.graph = graph::compile(g);
  return spec;
}

// A graph survives the trip through the protocol: the same message and the same texture id.
TEST(GraphProto, RoundTripKeepsMessageAndId) {
  for (const auto& g : {graph::testing::builtin_marble_graph(), graph::testing::warped_graph()}) {
    const TextureSpec spec = graph_spec(g);
    const v1::TextureSpec m = to_proto(spec);
    ASSERT_TRUE(m.has_graph());
    const TextureSpec again = from_proto(m);
    EXPECT_EQ(to_proto(again).SerializeAsString(), m.SerializeAsString());
    EXPECT_EQ(texture_id(again, Volume{}, 16, MipSettings{}),
              texture_id(spec, Volume{}, 16, MipSettings{}));
  }
}

TEST(GraphProto, ErrorsNameTheNodeAndInput) {
  v1::TextureSpec m;
  auto* node = m.mutable_graph()->add_nodes();
  node->set_name("n");
  node->set_category("noise3d");
  auto* input = node->add_inputs();
  input->set_name("pivot");
  input->set_node("nowhere");
  auto* out = m.mutable_graph()->add_outputs();
  out->set_channel(v1::CHANNEL_COLOUR);
  out->set_node("n");
  try {
    (void)from_proto(m);
    FAIL() << "accepted a reference to no node";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "graph.nodes[n].pivot");
  }
  input->clear_value();
  try {
    (void)from_proto(m);
    FAIL() << "accepted an unset input";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "graph.nodes[n].pivot");
  }
}

}  // namespace
}  // namespace soltex
