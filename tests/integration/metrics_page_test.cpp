// A live soltexd's /metrics page, after real traffic (bricks, bad keys, a message over the size
// limit, a cancelled stream), read by the Prometheus project's parser and, where installed,
// by promtool.
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include "brick_test_client.h"
#include "http_test_client.h"
#include "soltexd_process.h"

namespace soltex {
namespace {

using namespace testing;

// One unary call with raw request bytes, without credentials.
grpc::Status raw_unary_call(const SoltexdProcess& server, const std::string& method,
                            const std::string& request_bytes, std::string* response_bytes) {
  auto channel = grpc::CreateChannel(server.grpc_address(), grpc::InsecureChannelCredentials());
  grpc::GenericStub stub(channel);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  grpc::Slice slice(request_bytes);
  grpc::ByteBuffer request(&slice, 1), response;
  std::promise<grpc::Status> done;
  stub.UnaryCall(&context, method, grpc::StubOptions(), &request, &response,
                 [&](grpc::Status s) { done.set_value(s); });
  const grpc::Status status = done.get_future().get();
  std::vector<grpc::Slice> slices;
  if (status.ok() && response_bytes) (void)response.Dump(&slices);
  for (const auto& s : slices) {
    response_bytes->append(reinterpret_cast<const char*>(s.begin()), s.size());
  }
  return status;
}

// The health service's answer for `service`: 1 SERVING, or minus the failed call's code.
int health_of(const SoltexdProcess& server, const std::string& service) {
  // HealthCheckRequest{service}: field 1, length-delimited.
  std::string request = "\x0a" + std::string(1, static_cast<char>(service.size())) + service;
  std::string response;
  const grpc::Status status =
      raw_unary_call(server, "/grpc.health.v1.Health/Check", request, &response);
  if (!status.ok()) return -static_cast<int>(status.error_code());
  return response.size() == 2 && response[0] == 0x08 ? response[1] : -100;
}

// The exit status of a shell command, its output in `output`.
int run(const std::string& command, std::string& output) {
  const std::string log = ::testing::TempDir() + "/metrics_page_command.log";
  const int status = std::system((command + " > " + log + " 2>&1").c_str());
  std::ifstream in(log);
  output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string python() {
  // Debian's python3 carries python3-prometheus-client; a pyenv or venv python may not.
  return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

// Polls /metrics until `done` holds for the page (a stream's last counters are added when
// its state is released, just after the client sees the call end).
std::string metrics_when(const SoltexdProcess& server,
                         const std::function<bool(const std::string&)>& done) {
  std::string page;
  for (int i = 0; i < 100; ++i) {
    page = metrics(server);
    if (done(page)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return page;
}

// A stream that asks for many slow bricks, reads one batch and cancels.
void cancel_a_busy_stream(v1::BrickService::Stub& stub, uint64_t texture) {
  grpc::ClientContext context;
  auto stream = stub.StreamBricks(&context);
  std::vector<v1::BrickKey> keys = level_keys(texture, 0, 16);
  keys.resize(1000);
  ASSERT_TRUE(stream->Write(want(keys)));
  v1::BrickBatch batch;
  ASSERT_TRUE(stream->Read(&batch));
  context.TryCancel();
  while (stream->Read(&batch)) {
  }
  EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::CANCELLED);
}

// One BrickRequest of about 2 MiB of wanted keys on a stream.
void send_an_oversize_stream_message(v1::BrickService::Stub& stub, uint64_t texture) {
  std::vector<v1::BrickKey> keys(120000, key_of(texture, 0, 0, 0, 0));
  v1::BrickRequest request = want(keys);
  ASSERT_GT(request.ByteSizeLong(), 1u << 20);
  grpc::ClientContext context;
  auto stream = stub.StreamBricks(&context);
  stream->Write(request);  // may fail: the server may already have ended the call
  v1::BrickBatch batch;
  while (stream->Read(&batch)) {
  }
  EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
}

TEST(MetricsPage, ParsesAfterRealTrafficAndCountsWhatWasRefused) {
  SoltexdProcess server({"--threads", "1", "--max-message-bytes", "1048576"});
  EXPECT_EQ(health_of(server, ""), 1);
  EXPECT_EQ(health_of(server, "soltex.v1.BrickService"), 1);
  auto stub = connect(server);

  // Ordinary bricks, and a bad key answered with its code.
  const v1::TextureHandle small = register_texture(*stub, marble_request());
  std::vector<v1::BrickKey> keys = level_keys(small.id(), 3, 1);
  keys.push_back(key_of(small.id(), 9, 0, 0, 0));  // no level 9: OUT_OF_RANGE
  ASSERT_TRUE(stream_once(*stub, want(keys)).status.ok());

  // Messages over the 1 MiB limit, refused by gRPC before any handler sees them. A unary call's
  // request is dropped inside gRPC's core before the call reaches the C++ server (no counter
  // can see it); a stream's is counted as cut short.
  const std::string oversize(2u << 20, '\x01');
  EXPECT_EQ(raw_unary_call(server, "/soltex.v1.BrickService/RegisterTexture", oversize, nullptr)
                .error_code(),
            grpc::StatusCode::RESOURCE_EXHAUSTED);
  send_an_oversize_stream_message(*stub, small.id());

  v1::RegisterTextureRequest slow = marble_request(7, 8);
  slow.set_mip_mode(v1::MIP_MODE_SUPERSAMPLED);  // slow bricks: the queue stays full
  slow.set_supersample(4);
  cancel_a_busy_stream(*stub, register_texture(*stub, slow).id());

  const std::string page = metrics_when(server, [](const std::string& m) {
    return metric_value(m, "soltex_streams_open") == 0 &&
           metric_value(m, "soltex_bricks_requested_total") ==
               metric_value(m, "soltex_bricks_served_total") +
                   metric_value(m, "soltex_bricks_cancelled_total");
  });

  // Every brick requested was either sent or counted as cancelled.
  EXPECT_GT(metric_value(page, "soltex_bricks_cancelled_total"), 0.0) << page;
  EXPECT_EQ(metric_value(page, "soltex_bricks_requested_total"),
            metric_value(page, "soltex_bricks_served_total") +
                metric_value(page, "soltex_bricks_cancelled_total"))
      << page;
  EXPECT_EQ(metric_value(page, "soltex_errors_total{grpc_code=\"OUT_OF_RANGE\"}"), 1.0);

  const std::string unary =
      R"(grpc_type="unary",grpc_service="soltex.v1.BrickService",grpc_method="RegisterTexture")";
  EXPECT_EQ(metric_value(page, "grpc_server_handled_total{" + unary + R"(,grpc_code="OK"})"), 2.0)
      << page;
  // The oversize stream and the cancelled one: their status never reached the client.
  const std::string streams = R"(grpc_type="bidi_stream",grpc_service="soltex.v1.BrickService",)"
                              R"(grpc_method="StreamBricks")";
  EXPECT_EQ(metric_value(page, "grpc_server_started_total{" + streams + "}"), 3.0);
  EXPECT_EQ(metric_value(page, "soltex_grpc_calls_cut_short_total{" + streams + "}"), 2.0);
  EXPECT_EQ(
      metric_value(page, "grpc_server_handled_total{" + streams + R"(,grpc_code="CANCELLED"})"),
      2.0);
  EXPECT_EQ(metric_value(page, "grpc_server_handled_total{" + streams + R"(,grpc_code="OK"})"),
            1.0);
  EXPECT_GT(metric_value(page, "process_resident_memory_bytes"), 1e6);
  EXPECT_GT(metric_value(page, "process_open_fds"), 0.0);
  EXPECT_GT(metric_value(page, "process_start_time_seconds"), 1.6e9);
  EXPECT_NE(page.find("soltex_build_info{version=\""), std::string::npos);

  const std::string file = ::testing::TempDir() + "/soltexd_metrics.txt";
  std::ofstream(file) << page;
  std::string output;
  EXPECT_EQ(run(python() + " " + CHECK_METRICS_SCRIPT + " " + file +
                    " soltex_build_info process_cpu_seconds_total process_resident_memory_bytes"
                    " process_open_fds process_start_time_seconds grpc_server_handled_total"
                    " soltex_bricks_cancelled_total soltex_brick_latency_seconds"
                    " soltex_brick_stage_seconds",
                output),
            0)
      << output << "\n"
      << page;
  // promtool (Debian's prometheus package) where it is installed: the same parser Prometheus
  // scrapes with, plus its naming lint.
  if (run("command -v promtool", output) == 0) {
    EXPECT_EQ(run("promtool check metrics < " + file, output), 0) << output;
  }
}

TEST(MetricsPage, MethodsThatDoNotExistShareOneSeries) {
  SoltexdProcess server({"--threads", "1"});
  // Names a client made up, one of them in soltex's own service: each is UNIMPLEMENTED, and
  // none may add series of its own (the page and the server's memory would grow per name).
  const std::vector<std::string> invented = {"/made.Up/Method0", "/made.Up/Method1",
                                             "/soltex.v1.BrickService/NoSuchMethod", "/x"};
  for (const std::string& method : invented) {
    EXPECT_EQ(raw_unary_call(server, method, "", nullptr).error_code(),
              grpc::StatusCode::UNIMPLEMENTED)
        << method;
  }
  EXPECT_EQ(health_of(server, ""), 1);  // a defined method keeps its own series
  const std::string unknown =
      R"(grpc_type="bidi_stream",grpc_service="unknown",grpc_method="unknown")";
  const std::string page = metrics_when(server, [&](const std::string& m) {
    return metric_value(
               m, "grpc_server_handled_total{" + unknown + R"(,grpc_code="UNIMPLEMENTED"})") == 4.0;
  });
  EXPECT_EQ(metric_value(page, "grpc_server_started_total{" + unknown + "}"), 4.0) << page;
  EXPECT_EQ(
      metric_value(page, "grpc_server_handled_total{" + unknown + R"(,grpc_code="UNIMPLEMENTED"})"),
      4.0)
      << page;
  for (const char* name : {"made.Up", "Method0", "NoSuchMethod"}) {
    EXPECT_EQ(page.find(name), std::string::npos) << name << "\n" << page;
  }
  EXPECT_EQ(metric_value(page, R"(grpc_server_started_total{grpc_type="unary",)"
                               R"(grpc_service="grpc.health.v1.Health",grpc_method="Check"})"),
            1.0)
      << page;
}

TEST(MetricsPage, AUnaryRequestThatDoesNotParseIsInvalidArgumentNamingItsType) {
  SoltexdProcess server({"--threads", "1"});
  // A varint that never ends, and a field of wire type 5 cut short.
  for (const std::string& bytes : {std::string("\xff\xff\xff\xff\x0f"), std::string("\x0d\x00")}) {
    for (const std::string type : {"RegisterTextureRequest", "GetServerInfoRequest"}) {
      const std::string method =
          type == "RegisterTextureRequest" ? "RegisterTexture" : "GetServerInfo";
      const grpc::Status status =
          raw_unary_call(server, "/soltex.v1.BrickService/" + method, bytes, nullptr);
      EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << method;
      EXPECT_NE(status.error_message().find("is not a soltex.v1." + type), std::string::npos)
          << status.error_message();
    }
  }
  // The server goes on: a well-formed call still answers.
  auto stub = connect(server);
  EXPECT_GT(register_texture(*stub, marble_request()).id(), 0u);
  const std::string page = metrics(server);
  EXPECT_EQ(metric_value(page, R"(grpc_server_handled_total{grpc_type="unary",)"
                               R"(grpc_service="soltex.v1.BrickService",)"
                               R"(grpc_method="RegisterTexture",grpc_code="INVALID_ARGUMENT"})"),
            2.0)
      << page;
}

TEST(MetricsPage, AnswersHeadAndIgnoresAScrapersQuery) {
  SoltexdProcess server({"--threads", "1"});
  const int port = server.metrics_port();
  // Prometheus' `params` add a query; the page is the same.
  const testing::HttpReply queried = testing::http_request(port, "GET", "/metrics?module=soltex");
  EXPECT_EQ(queried.status, 200);
  EXPECT_NE(queried.body.find("# TYPE soltex_build_info gauge"), std::string::npos);
  const testing::HttpReply head = testing::http_request(port, "HEAD", "/metrics");
  EXPECT_EQ(head.status, 200);
  EXPECT_EQ(head.body, "");
  EXPECT_GT(std::stoul(head.header("content-length")), 1000u);
  const testing::HttpReply post = testing::http_request(port, "POST", "/metrics");
  EXPECT_EQ(post.status, 405);
  EXPECT_EQ(post.header("allow"), "GET, HEAD");
  EXPECT_EQ(testing::http_request(port, "GET", "/metric").status, 404);
}

}  // namespace
}  // namespace soltex
