// Graph textures through a real soltexd over loopback: registered by proto, served as bricks
// equal to local evaluation, refused with the node named, limits published.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include "../unit/graph/graph_builders.h"
#include "brick_test_client.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/texture_id.h"
#include "soltex/graph/compiled_graph.h"
#include "soltex/graph/graph_limits.h"
#include "soltex/spec_proto/spec_from_proto.h"
#include "soltexd_process.h"

namespace soltex {
namespace {

using namespace testing;

v1::RegisterTextureRequest graph_request(const graph::TextureGraph& g) {
  v1::RegisterTextureRequest request = marble_request(6, 8);
  TextureSpec spec;
  spec.graph = graph::compile(g);
  *request.mutable_spec() = to_proto(spec);
  return request;
}

// After a refusal: a good graph texture registers and its brick is served.
void expect_a_graph_is_still_served(v1::BrickService::Stub& stub) {
  const v1::TextureHandle good =
      register_texture(stub, graph_request(graph::testing::warped_graph()));
  const StreamResult result = stream_once(stub, want(level_keys(good.id(), 3, 1)));
  EXPECT_TRUE(result.status.ok());
  EXPECT_EQ(result.bricks.size(), 1u);
}

TEST(GraphTexture, ServedBricksEqualLocalEvaluation) {
  SoltexdProcess server;
  auto stub = connect(server);
  for (const auto& g : {graph::testing::warped_graph(), graph::testing::builtin_marble_graph()}) {
    const v1::RegisterTextureRequest registration = graph_request(g);
    const v1::TextureHandle handle = register_texture(*stub, registration);
    EXPECT_EQ(handle.id(),
              texture_id(from_proto(registration.spec()), from_proto(registration.volume()), 8));
    std::vector<v1::BrickKey> keys = level_keys(handle.id(), 3, 1);
    for (const auto& k : level_keys(handle.id(), 1, 4)) keys.push_back(k);
    const StreamResult result = stream_once(*stub, want(keys));
    ASSERT_TRUE(result.status.ok()) << result.status.error_message();
    ASSERT_EQ(result.bricks.size(), keys.size());
    EXPECT_TRUE(result.errors.empty());
    for (const v1::Brick& brick : result.bricks) {
      const DecodedBrick decoded = decode_brick(std::span(
          reinterpret_cast<const uint8_t*>(brick.payload().data()), brick.payload().size()));
      EXPECT_EQ(decoded.samples, local_brick(registration, brick.key()));
    }
  }
}

TEST(GraphTexture, InvalidGraphIsRefusedByNodeAndTheServerGoesOn) {
  SoltexdProcess server;
  auto stub = connect(server);
  v1::RegisterTextureRequest bad = graph_request(graph::testing::warped_graph());
  auto* node = bad.mutable_spec()->mutable_graph()->mutable_nodes(1);
  node->mutable_inputs(0)->set_node("q");  // p3 = q * 3, q = p3 + warp: a cycle
  grpc::ClientContext context;
  v1::TextureHandle handle;
  const grpc::Status status = stub->RegisterTexture(&context, bad, &handle);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("cycle"), std::string::npos) << status.error_message();
  EXPECT_NE(status.error_message().find("graph.nodes["), std::string::npos)
      << status.error_message();
  // Everyone else is still served.
  expect_a_graph_is_still_served(*stub);
}

TEST(GraphTexture, HugeCategoryIsRefusedWithAShortMessageAndTheServerGoesOn) {
  SoltexdProcess server;
  auto stub = connect(server);
  v1::RegisterTextureRequest bad = graph_request(graph::testing::warped_graph());
  bad.mutable_spec()->mutable_graph()->mutable_nodes(0)->set_category(std::string(100000, 'c'));
  grpc::ClientContext context;
  v1::TextureHandle handle;
  const grpc::Status status = stub->RegisterTexture(&context, bad, &handle);
  // Quoted whole, the category made a status larger than the client's metadata limit.
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
  EXPECT_LT(status.error_message().size(), 400u);
  EXPECT_NE(status.error_message().find("(100000 bytes)"), std::string::npos)
      << status.error_message();
  expect_a_graph_is_still_served(*stub);
}

TEST(GraphTexture, ServerInfoPublishesGraphLimits) {
  SoltexdProcess server;
  auto stub = connect(server);
  grpc::ClientContext context;
  v1::ServerInfo info;
  ASSERT_TRUE(stub->GetServerInfo(&context, {}, &info).ok());
  EXPECT_EQ(info.limits().max_graph_nodes(), static_cast<uint32_t>(graph::GraphLimits::kMaxNodes));
  EXPECT_EQ(info.limits().max_graph_depth(), static_cast<uint32_t>(graph::GraphLimits::kMaxDepth));
  EXPECT_EQ(info.limits().max_graph_cost(), graph::GraphLimits::kMaxCostPerSample);
}

}  // namespace
}  // namespace soltex
