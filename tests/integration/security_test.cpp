// soltexd's access control over loopback: bearer tokens, TLS with client certificates and the
// per-client bounds, against a real daemon.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "brick_test_client.h"
#include "soltex/net/channel_security.h"
#include "test_certificates.h"

namespace soltex {
namespace {

using namespace testing;

constexpr const char* kToken = "s3cret-token-for-tests";

std::vector<std::pair<std::string, std::string>> bearer(const std::string& token) {
  return {{"authorization", "Bearer " + token}};
}

grpc::Status server_info(v1::BrickService::Stub& stub, const std::string& token = "") {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
  v1::ServerInfo info;
  return stub.GetServerInfo(&context, {}, &info);
}

TEST(Security, EveryBrickServiceCallNeedsTheBearerToken) {
  const std::string token_file = write_temporary_file("token", std::string(kToken) + "\n");
  SoltexdProcess server({"--token-file", token_file});
  std::filesystem::remove(token_file);
  auto stub = connect(server);

  const grpc::Status missing = server_info(*stub);
  EXPECT_EQ(missing.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_NE(missing.error_message().find("Bearer <token>"), std::string::npos)
      << missing.error_message();
  const grpc::Status wrong = server_info(*stub, "not-the-token");
  EXPECT_EQ(wrong.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_NE(wrong.error_message().find("not valid"), std::string::npos);
  EXPECT_TRUE(server_info(*stub, kToken).ok());

  grpc::ClientContext context;
  v1::TextureHandle handle;
  EXPECT_EQ(stub->RegisterTexture(&context, marble_request(), &handle).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);

  v1::BrickRequest request = want({key_of(1, 0, 0, 0, 0)});
  *request.add_textures() = marble_request();
  EXPECT_EQ(stream_once(*stub, request).status.error_code(), grpc::StatusCode::UNAUTHENTICATED);

  // With the token, a stream that carries its texture is served.
  grpc::ClientContext register_context;
  register_context.AddMetadata("authorization", std::string("Bearer ") + kToken);
  ASSERT_TRUE(stub->RegisterTexture(&register_context, marble_request(), &handle).ok());
  const StreamResult served =
      stream_once(*stub, want({key_of(handle.id(), 3, 0, 0, 0)}), bearer(kToken));
  EXPECT_TRUE(served.status.ok()) << served.status.error_message();
  EXPECT_EQ(served.bricks.size(), 1u);

  // Probes carry no token: the health service stays open.
  EXPECT_EQ(health_status(server), 1);
  EXPECT_EQ(metric_value(metrics(server), "soltex_errors_total{grpc_code=\"UNAUTHENTICATED\"}"), 4);
}

TEST(Security, TlsWithClientCertificates) {
  const TestCertificates certs;
  SoltexdProcess server({"--tls-cert", certs.server_cert(), "--tls-key", certs.server_key(),
                         "--tls-client-ca", certs.ca()});
  const auto call = [&](const net::ChannelSecurity& security) {
    grpc::ChannelArguments args;
    auto stub = v1::BrickService::NewStub(net::open_channel(server.grpc_address(), security, args));
    return server_info(*stub);
  };
  net::ChannelSecurity trusted;
  trusted.tls_ca_file = certs.ca();
  trusted.tls_cert_file = certs.client_cert();
  trusted.tls_key_file = certs.client_key();
  EXPECT_TRUE(call(trusted).ok()) << call(trusted).error_message();

  net::ChannelSecurity named = trusted;  // the certificate names localhost too
  named.tls_server_name = "localhost";
  EXPECT_TRUE(call(named).ok());

  net::ChannelSecurity no_certificate;
  no_certificate.tls_ca_file = certs.ca();
  EXPECT_FALSE(call(no_certificate).ok());

  net::ChannelSecurity stranger = trusted;  // signed by a CA the server does not trust
  stranger.tls_cert_file = certs.other_client_cert();
  stranger.tls_key_file = certs.other_client_key();
  EXPECT_FALSE(call(stranger).ok());

  EXPECT_FALSE(call(net::ChannelSecurity{}).ok());  // plaintext to a TLS port
}

TEST(Security, ServerRefusesTlsHalfConfigured) {
  const TestCertificates certs;
  EXPECT_THROW(SoltexdProcess({"--tls-cert", certs.server_cert()}), std::runtime_error);
  EXPECT_THROW(SoltexdProcess({"--tls-client-ca", certs.ca()}), std::runtime_error);
}

TEST(Security, OneClientMayHoldOnlySoManyStreams) {
  SoltexdProcess server({"--max-streams-per-client", "2"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request());
  const v1::BrickRequest one = want({key_of(handle.id(), 3, 0, 0, 0)});

  // Two open streams, each answered once so the server has certainly counted it.
  grpc::ClientContext first_context, second_context;
  auto first = stub->StreamBricks(&first_context);
  auto second = stub->StreamBricks(&second_context);
  v1::BrickBatch batch;
  for (auto* stream : {first.get(), second.get()}) {
    ASSERT_TRUE(stream->Write(one));
    ASSERT_TRUE(stream->Read(&batch));
  }
  const StreamResult third = stream_once(*stub, one);
  EXPECT_EQ(third.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(third.status.error_message().find("max_streams_per_client"), std::string::npos)
      << third.status.error_message();

  // Closing one frees its slot (once the server has seen the call end).
  first->WritesDone();
  EXPECT_TRUE(first->Finish().ok());
  StreamResult fourth = stream_once(*stub, one);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!fourth.status.ok() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    fourth = stream_once(*stub, one);
  }
  EXPECT_TRUE(fourth.status.ok()) << fourth.status.error_message();
  EXPECT_EQ(fourth.bricks.size(), 1u);
  second->WritesDone();
  EXPECT_TRUE(second->Finish().ok());
}

TEST(Security, OneClientMayQueueOnlySoManyBricks) {
  SoltexdProcess server({"--max-queued-per-client", "16", "--threads", "1"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request(6, 8));
  const std::vector<v1::BrickKey> keys = level_keys(handle.id(), 1, 4);  // 64
  const StreamResult result = stream_once(*stub, want(keys));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  // The request is read whole before any worker takes from it: 16 queued, 48 refused.
  EXPECT_EQ(result.bricks.size(), 16u);
  ASSERT_EQ(result.errors.size(), 48u);
  EXPECT_EQ(result.errors[0].code(), static_cast<int>(grpc::StatusCode::RESOURCE_EXHAUSTED));
  EXPECT_NE(result.errors[0].message().find("max_queued_per_client"), std::string::npos)
      << result.errors[0].message();
  // The log says so once, not 48 times: what the operator reads to find the bound.
  const std::string log = server.log();
  EXPECT_NE(log.find(" refused: client 127.0.0.1 has 16 bricks queued over its streams "
                     "(max_queued_per_client)"),
            std::string::npos)
      << log;
  std::size_t lines = 0;
  for (std::size_t at = log.find("max_queued_per_client"); at != std::string::npos;
       at = log.find("max_queued_per_client", at + 1)) {
    ++lines;
  }
  EXPECT_EQ(lines, 1u) << log;
  // The server serves everyone else, and this client again once its queue drained.
  EXPECT_EQ(stream_once(*stub, want({keys[63]})).bricks.size(), 1u);
}

}  // namespace
}  // namespace soltex
