// No client can lock the others out, against a real soltexd on loopback: the texture
// registry evicts what no stream uses, limits follow the client's identity (its token's name,
// or the address a trusted proxy names), and SIGHUP reloads tokens and certificates without
// dropping open streams.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "brick_test_client.h"
#include "soltex/net/channel_security.h"
#include "test_certificates.h"

namespace soltex {
namespace {

using namespace testing;
using Metadata = std::vector<std::pair<std::string, std::string>>;

Metadata bearer(const std::string& token) {
  return {{"authorization", "Bearer " + token}};
}

// Distinct textures, as the client that filled the registry made them: stripes of width
// 1 + i * 1e-3.
v1::RegisterTextureRequest stripes(int i) {
  v1::RegisterTextureRequest request = marble_request(6, 8);
  request.mutable_spec()->mutable_stripes()->set_width(1.0 + i * 1e-3);
  return request;
}

grpc::Status register_as(v1::BrickService::Stub& stub, const v1::RegisterTextureRequest& request,
                         const Metadata& metadata = {}, v1::TextureHandle* handle = nullptr) {
  grpc::ClientContext context;
  for (const auto& [name, value] : metadata) context.AddMetadata(name, value);
  v1::TextureHandle ignored;
  return stub.RegisterTexture(&context, request, handle ? handle : &ignored);
}

// One brick of `registration`, the texture carried on the stream's first message.
StreamResult carried(v1::BrickService::Stub& stub, const v1::RegisterTextureRequest& registration,
                     uint64_t id, const Metadata& metadata = {}) {
  v1::BrickRequest request = want({key_of(id, 3, 0, 0, 0)});
  *request.add_textures() = registration;
  return stream_once(stub, request, metadata);
}

// Polls /metrics until `name` reads `value` (a SIGHUP is handled asynchronously).
bool wait_for_metric(const SoltexdProcess& server, const std::string& name, double value) {
  for (int i = 0; i < 1000; ++i) {
    if (metric_value(metrics(server), name) == value) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

std::string tokens_file(const std::string& text) {
  return write_temporary_file("tokens", text);
}

TEST(Registry, OneClientFillingItCannotRefuseAnothersTexture) {
  const std::string tokens = tokens_file("filler AAAA\nviewer BBBB\n");
  SoltexdProcess server({"--token-file", tokens, "--max-textures-per-client", "256"});
  auto stub = connect(server);
  // The registration that once locked everyone out until a restart: 992 distinct textures.
  for (int i = 0; i < 992; ++i) {
    ASSERT_TRUE(register_as(*stub, stripes(i), bearer("AAAA")).ok()) << i;
  }
  v1::TextureHandle handle;
  const v1::RegisterTextureRequest mine = stripes(5000);
  ASSERT_TRUE(register_as(*stub, mine, bearer("BBBB"), &handle).ok());
  const StreamResult served = carried(*stub, mine, handle.id(), bearer("BBBB"));
  EXPECT_TRUE(served.status.ok()) << served.status.error_message();
  EXPECT_EQ(served.bricks.size(), 1u);
  EXPECT_TRUE(served.request_errors.empty());

  // The filler churned its own share (--max-textures-per-client).
  const std::string m = metrics(server);
  EXPECT_EQ(metric_value(m, "soltex_textures_registered"), 257.0);
  EXPECT_EQ(metric_value(m, "soltex_textures_evicted_total"), 992.0 - 256.0);
  EXPECT_GT(metric_value(m, "soltex_texture_registry_bytes"), 0.0);
  std::filesystem::remove(tokens);
}

TEST(Registry, AFullRegistryEvictsWhatNoStreamUsesAndAnEvictedTextureRegistersAgain) {
  SoltexdProcess server({"--max-textures", "2"});
  auto stub = connect(server);
  v1::TextureHandle first, second;
  ASSERT_TRUE(register_as(*stub, stripes(1), {}, &first).ok());
  ASSERT_TRUE(register_as(*stub, stripes(2), {}, &second).ok());
  ASSERT_TRUE(register_as(*stub, stripes(3)).ok());  // stripes(1), least recently used, goes
  const StreamResult gone = stream_once(*stub, want({key_of(first.id(), 3, 0, 0, 0)}));
  ASSERT_EQ(gone.errors.size(), 1u);
  EXPECT_EQ(gone.errors[0].code(), static_cast<int>(grpc::StatusCode::NOT_FOUND));
  EXPECT_NE(gone.errors[0].message().find("evicted"), std::string::npos);

  v1::TextureHandle again;
  ASSERT_TRUE(register_as(*stub, stripes(1), {}, &again).ok());
  EXPECT_EQ(again.id(), first.id());  // content-addressed: the same id
  EXPECT_EQ(stream_once(*stub, want({key_of(first.id(), 3, 0, 0, 0)})).bricks.size(), 1u);
  // stripes(2) went to make room for stripes(1) again; a client that carries its textures on
  // the stream never notices.
  const StreamResult carrying = carried(*stub, stripes(2), second.id());
  EXPECT_TRUE(carrying.request_errors.empty());
  EXPECT_EQ(carrying.bricks.size(), 1u);
  EXPECT_EQ(metric_value(metrics(server), "soltex_textures_evicted_total"), 3.0);
}

TEST(Registry, TexturesInUseByOpenStreamsAreKept) {
  SoltexdProcess server({"--max-textures", "2"});
  auto stub = connect(server);
  // Two open streams, each using its own texture (carried in its first message).
  grpc::ClientContext context_a, context_b;
  auto stream_a = stub->StreamBricks(&context_a);
  auto stream_b = stub->StreamBricks(&context_b);
  std::vector<uint64_t> ids;
  v1::BrickBatch batch;
  for (auto [stream, i] : {std::pair{stream_a.get(), 1}, std::pair{stream_b.get(), 2}}) {
    v1::TextureHandle handle;
    ASSERT_TRUE(register_as(*stub, stripes(i), {}, &handle).ok());
    ids.push_back(handle.id());
    v1::BrickRequest request = want({key_of(handle.id(), 3, 0, 0, 0)});
    *request.add_textures() = stripes(i);
    ASSERT_TRUE(stream->Write(request));
    ASSERT_TRUE(stream->Read(&batch));
    ASSERT_EQ(batch.bricks_size(), 1);
  }
  // Nothing can be evicted: a new texture is refused, naming the bound.
  const grpc::Status refused = register_as(*stub, stripes(3));
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(refused.error_message().find("in use by an open stream"), std::string::npos)
      << refused.error_message();
  EXPECT_NE(refused.error_message().find("max_textures"), std::string::npos);
  // The streams go on with their textures.
  ASSERT_TRUE(stream_a->Write(want({key_of(ids[0], 2, 0, 0, 0)})));
  ASSERT_TRUE(stream_a->Read(&batch));
  EXPECT_EQ(batch.bricks_size(), 1);
  // Once one stream ends its texture may go, and the new one is registered.
  stream_a->WritesDone();
  while (stream_a->Read(&batch)) {
  }
  EXPECT_TRUE(stream_a->Finish().ok());
  grpc::Status later = register_as(*stub, stripes(3));
  for (int i = 0; i < 500 && !later.ok(); ++i) {  // until the server has seen the stream end
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    later = register_as(*stub, stripes(3));
  }
  EXPECT_TRUE(later.ok()) << later.error_message();
  EXPECT_GE(metric_value(metrics(server),
                         "soltex_texture_registrations_refused_total{reason=\"registry_full\"}"),
            1.0);
  stream_b->WritesDone();
  while (stream_b->Read(&batch)) {
  }
  EXPECT_TRUE(stream_b->Finish().ok());
}

// A stream held open: written once and answered, so the server has certainly counted it.
struct OpenStream {
  grpc::ClientContext context;
  std::unique_ptr<grpc::ClientReaderWriter<v1::BrickRequest, v1::BrickBatch>> stream;

  OpenStream(v1::BrickService::Stub& stub, const Metadata& metadata, uint64_t texture) {
    for (const auto& [name, value] : metadata) context.AddMetadata(name, value);
    stream = stub.StreamBricks(&context);
    v1::BrickBatch batch;
    ok = stream->Write(want({key_of(texture, 3, 0, 0, 0)})) && stream->Read(&batch) &&
         batch.bricks_size() == 1;
  }
  // More bricks on the same stream: it is still served.
  bool serves(uint64_t texture, int level) {
    v1::BrickBatch batch;
    return stream->Write(want({key_of(texture, level, 0, 0, 0)})) && stream->Read(&batch) &&
           batch.bricks_size() == 1;
  }
  grpc::Status close() {
    stream->WritesDone();
    v1::BrickBatch batch;
    while (stream->Read(&batch)) {
    }
    return stream->Finish();
  }
  bool ok = false;
};

grpc::StatusCode stream_status(v1::BrickService::Stub& stub, uint64_t texture,
                               const Metadata& metadata, std::string* message = nullptr) {
  const StreamResult result = stream_once(stub, want({key_of(texture, 3, 0, 0, 0)}), metadata);
  if (message) *message = result.status.error_message();
  return result.status.error_code();
}

TEST(Identity, TwoNamedTokensAreTwoClientsWhereverTheyComeFrom) {
  const std::string tokens = tokens_file("# one line per client\nalice AAAA\nbob BBBB\n");
  SoltexdProcess server({"--token-file", tokens, "--max-streams-per-client", "1"});
  auto stub = connect(server);
  v1::TextureHandle handle;
  ASSERT_TRUE(register_as(*stub, stripes(1), bearer("AAAA"), &handle).ok());
  OpenStream alice(*stub, bearer("AAAA"), handle.id());
  ASSERT_TRUE(alice.ok);
  // Same address, another token: another client.
  EXPECT_EQ(stream_status(*stub, handle.id(), bearer("BBBB")), grpc::StatusCode::OK);
  std::string message;
  constexpr int kRefused = 20;
  for (int i = 0; i < kRefused; ++i) {
    EXPECT_EQ(stream_status(*stub, handle.id(), bearer("AAAA"), &message),
              grpc::StatusCode::RESOURCE_EXHAUSTED);
  }
  EXPECT_NE(message.find("client token:alice already has 1 open brick streams"), std::string::npos)
      << message;
  EXPECT_TRUE(alice.close().ok());

  // Refusals are logged at most once a second per client; what was left out is counted.
  const std::string log = server.log();
  std::size_t lines = 0;
  for (auto at = log.find("stream from token:alice"); at != std::string::npos;
       at = log.find("stream from token:alice", at + 1)) {
    ++lines;
  }
  EXPECT_GE(lines, 1u);
  EXPECT_EQ(static_cast<double>(lines) +
                metric_value(metrics(server), "soltex_refusal_log_lines_suppressed_total"),
            kRefused);
  std::filesystem::remove(tokens);
}

TEST(Identity, ATrustedProxyNamesTheClientOthersCannot) {
  const auto forwarded = [](const std::string& address) {
    return Metadata{{"x-forwarded-for", address}};
  };
  for (const bool trusted : {true, false}) {
    std::vector<std::string> args = {"--max-streams-per-client", "1"};
    if (trusted) args.insert(args.end(), {"--trusted-proxies", "10.9.9.9,127.0.0.0/8"});
    SoltexdProcess server(args);
    auto stub = connect(server);
    v1::TextureHandle handle;
    ASSERT_TRUE(register_as(*stub, stripes(1), {}, &handle).ok());
    OpenStream first(*stub, forwarded("192.0.2.1"), handle.id());
    ASSERT_TRUE(first.ok);
    std::string message;
    // Behind a trusted proxy 192.0.2.2 is another client; from anyone else the header is
    // the client's own word and means nothing: both are 127.0.0.1.
    EXPECT_EQ(stream_status(*stub, handle.id(), forwarded("192.0.2.2"), &message),
              trusted ? grpc::StatusCode::OK : grpc::StatusCode::RESOURCE_EXHAUSTED)
        << message;
    EXPECT_EQ(stream_status(*stub, handle.id(), forwarded("192.0.2.1"), &message),
              grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(message.find(trusted ? "client 192.0.2.1 " : "client 127.0.0.1 "), std::string::npos)
        << message;
    EXPECT_TRUE(first.close().ok());
  }
}

TEST(Identity, TheOldFlagIsRefusedNamingItsReplacement) {
  try {
    SoltexdProcess server({"--trust-forwarded-for"});
    FAIL() << "soltexd started with --trust-forwarded-for";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("--trusted-proxies"), std::string::npos) << e.what();
  }
  try {
    SoltexdProcess server({"--trusted-proxies", "nginx"});
    FAIL() << "soltexd started with a trusted proxy that is no address";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'nginx' is not an IPv4 or IPv6 address"),
              std::string::npos)
        << e.what();
  }
}

TEST(Reload, SighupReloadsTheTokensFileAndOpenStreamsGoOn) {
  const std::string tokens = tokens_file("alice AAAA\nbob BBBB\n");
  SoltexdProcess server({"--token-file", tokens});
  auto stub = connect(server);
  v1::TextureHandle handle;
  ASSERT_TRUE(register_as(*stub, stripes(1), bearer("AAAA"), &handle).ok());
  OpenStream alice(*stub, bearer("AAAA"), handle.id());
  ASSERT_TRUE(alice.ok);

  std::ofstream(tokens) << "bob BBBB\ncarol CCCC\n";
  server.send_signal(SIGHUP);
  ASSERT_TRUE(wait_for_metric(server, "soltex_config_reloads_total{result=\"ok\"}", 1.0));
  EXPECT_TRUE(alice.serves(handle.id(), 2));  // admitted before: goes on
  EXPECT_EQ(stream_status(*stub, handle.id(), bearer("AAAA")), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(register_as(*stub, stripes(2), bearer("AAAA")).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(stream_status(*stub, handle.id(), bearer("BBBB")), grpc::StatusCode::OK);
  EXPECT_EQ(stream_status(*stub, handle.id(), bearer("CCCC")), grpc::StatusCode::OK);

  // A broken file changes nothing: the error is logged and counted.
  std::ofstream(tokens) << "bob BBBB extra-field\n";
  server.send_signal(SIGHUP);
  ASSERT_TRUE(wait_for_metric(server, "soltex_config_reloads_total{result=\"failed\"}", 1.0));
  EXPECT_EQ(stream_status(*stub, handle.id(), bearer("CCCC")), grpc::StatusCode::OK);
  EXPECT_NE(server.log().find("line 1: expected 'NAME TOKEN' or 'TOKEN', found 3 fields"),
            std::string::npos);
  EXPECT_TRUE(alice.serves(handle.id(), 1));
  EXPECT_TRUE(alice.close().ok());
  std::filesystem::remove(tokens);
}

std::unique_ptr<v1::BrickService::Stub> tls_stub(const SoltexdProcess& server,
                                                 const std::string& ca) {
  net::ChannelSecurity security;
  security.tls_ca_file = ca;
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // a connection of its own, a handshake
  return v1::BrickService::NewStub(net::open_channel(server.grpc_address(), security, args));
}

grpc::Status server_info(v1::BrickService::Stub& stub) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  v1::ServerInfo info;
  return stub.GetServerInfo(&context, {}, &info);
}

TEST(Reload, SighupReloadsTheCertificateAndOpenStreamsGoOn) {
  const TestCertificates before, after;  // two authorities, a server certificate from each
  const std::string cert = write_temporary_file("cert", "");
  const std::string key = write_temporary_file("key", "");
  std::filesystem::copy_file(before.server_cert(), cert,
                             std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(before.server_key(), key,
                             std::filesystem::copy_options::overwrite_existing);
  SoltexdProcess server({"--tls-cert", cert, "--tls-key", key});
  auto old_stub = tls_stub(server, before.ca());
  ASSERT_TRUE(server_info(*old_stub).ok());
  v1::TextureHandle handle;
  ASSERT_TRUE(register_as(*old_stub, stripes(1), {}, &handle).ok());
  OpenStream open(*old_stub, {}, handle.id());
  ASSERT_TRUE(open.ok);

  std::filesystem::copy_file(after.server_cert(), cert,
                             std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(after.server_key(), key,
                             std::filesystem::copy_options::overwrite_existing);
  server.send_signal(SIGHUP);
  ASSERT_TRUE(wait_for_metric(server, "soltex_config_reloads_total{result=\"ok\"}", 1.0));
  // New connections get the new certificate: trusted by the new authority only.
  EXPECT_TRUE(server_info(*tls_stub(server, after.ca())).ok());
  EXPECT_FALSE(server_info(*tls_stub(server, before.ca())).ok());
  // The stream on the old connection goes on.
  EXPECT_TRUE(open.serves(handle.id(), 2));
  EXPECT_TRUE(open.close().ok());
  std::filesystem::remove(cert);
  std::filesystem::remove(key);
}

// A certificate and a key that are not a pair: refused at start, naming both files (not as an
// address in use), and on SIGHUP counted as a failed reload that keeps the pair loaded before.
TEST(Reload, ACertificateAndKeyThatAreNotAPairAreRefused) {
  const TestCertificates certs, other;
  EXPECT_THROW(SoltexdProcess({"--tls-cert", certs.server_cert(), "--tls-key", other.server_key()}),
               std::runtime_error);
  const std::string cert = write_temporary_file("cert", "");
  std::filesystem::copy_file(certs.server_cert(), cert,
                             std::filesystem::copy_options::overwrite_existing);
  SoltexdProcess server({"--tls-cert", cert, "--tls-key", certs.server_key()});
  std::filesystem::copy_file(other.server_cert(), cert,
                             std::filesystem::copy_options::overwrite_existing);
  server.send_signal(SIGHUP);
  ASSERT_TRUE(wait_for_metric(server, "soltex_config_reloads_total{result=\"failed\"}", 1.0));
  EXPECT_EQ(metric_value(metrics(server), "soltex_config_reloads_total{result=\"ok\"}"), 0.0);
  EXPECT_TRUE(server_info(*tls_stub(server, certs.ca())).ok()) << "the old pair still serves";
  std::filesystem::remove(cert);
}

}  // namespace
}  // namespace soltex
