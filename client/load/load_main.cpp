// soltex-load: puts a measured, bounded load on one soltexd and reports per-brick throughput,
// latency percentiles and errors by status code.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "http_load.h"
#include "load_generator.h"
#include "load_options.h"
#include "load_report.h"
#include "progress_bar.h"
#include "request_log.h"
#include "soltex/cli/tool_cli.h"
#include "soltex/net/channel_security_options.h"

int main(int argc, char** argv) {
  using namespace soltex::load;
  namespace cli = soltex::cli;
  LoadOptions options;
  CLI::App app{"soltex-load: load generator for soltexd (closed or open loop, per-brick latency)"};
  std::string log_level = "info";
  cli::add_common_options(app, "soltex-load", log_level);
  add_load_options(app, options);
  soltex::net::ChannelSecurityOptions security;
  soltex::net::add_channel_security_options(app, security);
  if (const auto exit_code = cli::parse(app, "soltex-load", argc, argv)) return *exit_code;
  cli::start_logging("soltex-load", log_level);
  cli::prepare_for_grpc_streams();
  try {
    options.security = soltex::net::finish_channel_security(
        security, cli::value_from_environment(*app.get_option("--token"), argc, argv)
                      ? soltex::net::TokenOrigin::environment
                      : soltex::net::TokenOrigin::typed);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soltex-load: %s\n",
                 cli::with_value_source(app, e.what(), argc, argv).c_str());
    return cli::kExitUsage;
  }

  if (!options.http && options.mix == MixKind::hot && !options.open_loop() &&
      options.in_flight > options.hot_set) {
    // A stream never waits for one key twice at once, so it cannot keep more than the hot
    // set outstanding; the rest wait on the client and the run measures that, not the server.
    std::fprintf(stderr,
                 "soltex-load: warning: --in-flight %d exceeds --hot-set %d; at most %d bricks "
                 "can be outstanding per stream\n",
                 options.in_flight, options.hot_set, options.hot_set);
  }
  if (options.http) {
    // gRPC's knobs: an HTTP run has no streams, and one request at a time per connection.
    // Refused when typed; a SOLTEX_STREAMS kept in the environment for gRPC runs is left be.
    for (const char* name : {"--streams", "--in-flight"}) {
      if (cli::on_command_line(*app.get_option(name), argc, argv)) {
        std::fprintf(stderr,
                     "soltex-load: %s does not apply to --http, which sends one request at a time "
                     "on each of --connections\n",
                     name);
        return cli::kExitUsage;
      }
    }
    try {
      const HttpLoadResult result = run_http_load(options);
      std::cout << format_http_result(result, options.format) << std::flush;
      if (result.connection_errors > 0) {
        // As a gRPC stream ending in error: the server went away or dropped connections.
        std::fprintf(stderr,
                     "soltex-load: %llu HTTP exchanges failed at the connection (refused, reset "
                     "or closed unanswered); see the report\n",
                     static_cast<unsigned long long>(result.connection_errors));
        return cli::kExitFailure;
      }
    } catch (const LoadOptionsError& e) {
      std::fprintf(stderr, "soltex-load: %s\n",
                   cli::with_value_source(app, e.what(), argc, argv).c_str());
      return cli::kExitUsage;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "soltex-load: %s\n", e.what());
      return cli::kExitFailure;
    }
    return cli::kExitOk;
  }
  soltex::ProgressBar bar;
  ProgressCallback progress;
  if (options.progress) {
    progress = [&bar](const ProgressLine& line) { bar.show(format_progress(line)); };
  }
  try {
    const LoadResult result = run_load(options, progress);
    bar.finish();
    std::cout << format_result(result, options.format) << std::flush;
    if (result.stream_failures() > 0) {
      // The server went away or refused the streams: not a run to take figures from.
      std::fprintf(stderr, "soltex-load: %llu of %d streams ended with an error; see the report\n",
                   static_cast<unsigned long long>(result.stream_failures()), options.streams);
      return cli::kExitFailure;
    }
  } catch (const LoadOptionsError& e) {
    std::fprintf(stderr, "soltex-load: %s\n",
                 cli::with_value_source(app, e.what(), argc, argv).c_str());
    return cli::kExitUsage;
  } catch (const RequestLogFormatError& e) {
    // A --replay-file that does not parse: bad input, as a scene file is to soltex-view.
    std::fprintf(stderr, "soltex-load: %s\n", e.what());
    return cli::kExitUsage;
  } catch (const LoadSetupError& e) {
    std::fprintf(stderr, "soltex-load: %s\n", e.what());
    return cli::kExitFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soltex-load: %s\n", e.what());
    return cli::kExitFailure;
  }
  return cli::kExitOk;
}
