#include "client_access.h"

#include <gtest/gtest.h>

namespace soltex::server {
namespace {

TEST(ClientAccess, BoundsStreamsPerClientAndFreesSlotsOnRelease) {
  AccessConfig config;
  config.max_streams_per_client = 2;
  ClientAccess access(config);
  grpc::Status refusal;
  auto first = access.open_stream("10.0.0.1", refusal);
  auto second = access.open_stream("10.0.0.1", refusal);
  ASSERT_TRUE(first && second);
  EXPECT_FALSE(access.open_stream("10.0.0.1", refusal));
  EXPECT_EQ(refusal.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(refusal.error_message().find("max_streams_per_client"), std::string::npos);
  EXPECT_NE(refusal.error_message().find("10.0.0.1"), std::string::npos);

  // Another client is not affected.
  EXPECT_TRUE(access.open_stream("10.0.0.2", refusal));

  first->release();
  first->release();  // idempotent: frees one slot, not two
  auto third = access.open_stream("10.0.0.1", refusal);
  EXPECT_TRUE(third);
  EXPECT_FALSE(access.open_stream("10.0.0.1", refusal));
}

TEST(ClientAccess, StreamsOfOneClientShareItsQueuedCount) {
  ClientAccess access(AccessConfig{});
  grpc::Status refusal;
  auto a = access.open_stream("192.0.2.7", refusal);
  auto b = access.open_stream("192.0.2.7", refusal);
  a->usage().queued += 5;
  EXPECT_EQ(b->usage().queued.load(), 5);
  EXPECT_EQ(&a->usage(), &b->usage());
}

TEST(ClientAccess, NoTokenConfiguredMeansNoTokenRequired) {
  EXPECT_FALSE(ClientAccess(AccessConfig{}).token_required());
  AccessConfig config;
  config.token = "t";
  EXPECT_TRUE(ClientAccess(config).token_required());
}

}  // namespace
}  // namespace soltex::server
