#include "client_access.h"

#include <grpcpp/test/server_context_test_spouse.h>
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
  config.tokens = {{"", "t"}};
  EXPECT_TRUE(ClientAccess(config).token_required());
}

// The identity a call with `authorization` (none when empty) gets, or "refused: MESSAGE".
std::string identify(const ClientAccess& access, const std::string& authorization) {
  grpc::ServerContext context;
  grpc::testing::ServerContextTestSpouse spouse(&context);
  if (!authorization.empty()) spouse.AddClientMetadata("authorization", authorization);
  std::string client;
  const grpc::Status status = access.identify(context, client);
  return status.ok() ? client : "refused: " + status.error_message();
}

TEST(ClientAccess, ANamedTokenIsTheClientAnUnnamedOneLeavesTheAddress) {
  AccessConfig config;
  config.tokens = {{"alice", "secret-a"}, {"alice", "secret-a2"}, {"", "shared-secret"}};
  ClientAccess access(config);
  EXPECT_EQ(identify(access, "Bearer secret-a"), "token:alice");
  EXPECT_EQ(identify(access, "Bearer secret-a2"), "token:alice");  // rotation: one client
  // No peer in a test context: the address is empty, as it would be the peer's otherwise.
  EXPECT_EQ(identify(access, "Bearer shared-secret"), "");
  EXPECT_NE(identify(access, "Bearer secret-b").find("not valid"), std::string::npos);
  EXPECT_NE(identify(access, "").find("requires a bearer token"), std::string::npos);
  EXPECT_NE(identify(access, "Basic abc").find("'Bearer <token>'"), std::string::npos);
}

TEST(ClientAccess, ReplacedTokensApplyToLaterCalls) {
  AccessConfig config;
  config.tokens = {{"alice", "secret-a"}, {"bob", "secret-b"}};
  ClientAccess access(config);
  access.replace_tokens({{"bob", "secret-b"}});
  EXPECT_NE(identify(access, "Bearer secret-a").find("not valid"), std::string::npos);
  EXPECT_EQ(identify(access, "Bearer secret-b"), "token:bob");
  EXPECT_THROW(access.replace_tokens({}), std::invalid_argument);
  EXPECT_EQ(identify(access, "Bearer secret-b"), "token:bob");
}

std::vector<AddressRange> proxies(const std::vector<std::string>& texts) {
  return parse_address_ranges(texts);
}

TEST(ClientAddress, OnlyATrustedPeerIsBelievedAboutTheClient) {
  const auto trusted = proxies({"10.0.0.5", "fd00::/8"});
  // A peer that is no trusted proxy is the client, whatever its header says.
  EXPECT_EQ(client_address("192.0.2.1", {"198.51.100.9"}, trusted), "192.0.2.1");
  EXPECT_EQ(client_address("192.0.2.1", {"198.51.100.9"}, {}), "192.0.2.1");
  // A trusted one names the client.
  EXPECT_EQ(client_address("10.0.0.5", {"198.51.100.9"}, trusted), "198.51.100.9");
  EXPECT_EQ(client_address("fd00::17", {"2001:db8::1"}, trusted), "2001:db8::1");
  // Without a header it is the client itself.
  EXPECT_EQ(client_address("10.0.0.5", {}, trusted), "10.0.0.5");
}

TEST(ClientAddress, WhatTheClientWroteItselfIsSkipped) {
  const auto trusted = proxies({"10.0.0.0/24"});
  // The client sent "1.2.3.4" itself; nginx appended what it saw, then a second proxy.
  EXPECT_EQ(client_address("10.0.0.5", {"1.2.3.4", "198.51.100.9", "10.0.0.7"}, trusted),
            "198.51.100.9");
  // Every entry is a proxy of ours: the first one is where the call came from.
  EXPECT_EQ(client_address("10.0.0.5", {"10.0.0.8", "10.0.0.7"}, trusted), "10.0.0.8");
  // Not an address: no proxy of ours wrote it; the peer stays the client.
  EXPECT_EQ(client_address("10.0.0.5", {"unknown"}, trusted), "10.0.0.5");
}

TEST(AddressRange, ParsesAddressesAndBlocksAndNamesWhatIsWrong) {
  const AddressRange block = AddressRange::parse("10.1.0.0/16");
  EXPECT_TRUE(block.contains(*IpAddress::parse("10.1.200.3")));
  EXPECT_FALSE(block.contains(*IpAddress::parse("10.2.0.1")));
  EXPECT_TRUE(block.contains(*IpAddress::parse("::ffff:10.1.0.1")));  // IPv4-mapped
  EXPECT_TRUE(AddressRange::parse("0.0.0.0/0").contains(*IpAddress::parse("203.0.113.1")));
  EXPECT_FALSE(AddressRange::parse("0.0.0.0/0").contains(*IpAddress::parse("2001:db8::1")));
  EXPECT_TRUE(AddressRange::parse("::1").contains(*IpAddress::parse("[::1]")));
  EXPECT_TRUE(AddressRange::parse("2001:db8::/33").contains(*IpAddress::parse("2001:db8:7fff::")));
  EXPECT_FALSE(AddressRange::parse("2001:db8::/33").contains(*IpAddress::parse("2001:db8:8000::")));
  for (const char* bad : {"nginx", "10.0.0.0/33", "10.0.0.0/", "::/129", "10.0.0.0/8x", ""}) {
    try {
      AddressRange::parse(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + std::string(bad) + "'"), std::string::npos)
          << e.what();
    }
  }
}

TEST(AddressRange, PeerStringsGiveTheirHost) {
  EXPECT_EQ(host_of_peer("ipv4:127.0.0.1:5000"), "127.0.0.1");
  EXPECT_EQ(host_of_peer("ipv6:[::1]:5000"), "::1");
  EXPECT_EQ(host_of_peer("ipv6:%5B::1%5D:5000"), "::1");
  EXPECT_EQ(host_of_peer("unix:/tmp/socket"), "unix:/tmp/socket");
}

}  // namespace
}  // namespace soltex::server
