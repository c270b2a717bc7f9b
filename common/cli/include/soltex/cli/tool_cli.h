#pragma once

#include <CLI/CLI.hpp>
#include <initializer_list>
#include <optional>
#include <string>

// The conventions every soltex tool's command line follows, in one place so that the five
// tools cannot drift apart: --version, a validated --log-level with logs on stderr, an
// environment variable SOLTEX_<NAME> for every option, and one table of exit codes.
namespace soltex::cli {

// README.md, "Exit codes". Every tool uses the first three; 3 is soltex-view's alone.
inline constexpr int kExitOk = 0;            // done (also --help and --version)
inline constexpr int kExitFailure = 1;       // a runtime failure: network, server, files
inline constexpr int kExitUsage = 2;         // bad usage or input: options, environment, files
inline constexpr int kExitNotConverged = 3;  // soltex-view: written, but not converged

// The CMake project version, e.g. "0.1.0".
const char* version();

// The names spdlog knows, as --log-level accepts them.
inline constexpr const char* kLogLevels[] = {"trace", "debug",    "info", "warn",
                                             "error", "critical", "off"};

// Adds --version (prints "TOOL VERSION") and --log-level (one of kLogLevels; anything else
// is refused rather than read as "off", which is what spdlog makes of an unknown name).
void add_common_options(CLI::App& app, const std::string& tool, std::string& log_level);

// An environment variable renamed: the old name still sets the option, with a warning.
struct DeprecatedEnvironmentName {
  const char* old_name;
  const char* new_name;
};

// Gives every option that has none an environment variable named after its first long name
// (--metrics-listen: SOLTEX_METRICS_LISTEN), in the app, its option groups and subcommands,
// then parses. The command line wins over a config file, which wins over the environment.
// Returns the exit code when the tool should stop now: 0 after --help or --version, 2 after
// any parse or validation error (CLI11's own codes, 105, 109, ..., say nothing to a script).
std::optional<int> parse(CLI::App& app, const std::string& tool, int argc, char** argv,
                         std::initializer_list<DeprecatedEnvironmentName> deprecated = {});

// A number in [min, max] as CLI::Range checks one, except that NaN is refused too (every
// comparison with NaN is false, so CLI::Range lets it through). For floating-point options.
CLI::Validator NumberIn(double min, double max);

// Whether argv gives `option` by one of its long names ("--name" or "--name=value"), as opposed
// to the environment or a config file.
bool on_command_line(const CLI::Option& option, int argc, char** argv);

// Whether `option`'s value is its environment variable's: not given on the command line, and
// the variable set to what the option holds (a config file's value would differ or be alone).
bool value_from_environment(const CLI::Option& option, int argc, char** argv);

// `message` ("--name VALUE: ..." or "--name: ...", about one of app's options), with where the
// value came from when the command line did not give it: " (from the environment variable X)"
// or the config file; other options it names further on get "--other from ..." in the same
// parentheses. For a tool's own checks after parsing, which CLI11 cannot annotate.
std::string with_value_source(const CLI::App& app, const std::string& message, int argc,
                              char** argv);

// A whole number in [min, max], for integer options: text that is not one ("abc", "1.5") is
// refused as not a whole number rather than as out of range, as CLI::Range words it.
CLI::Validator IntegerIn(long long min, long long max);

// A server to dial: HOST:PORT (a name, an IPv4 address or a bracketed IPv6 one, the port in
// [1, 65535]) or a gRPC target with a scheme (unix:PATH, dns:///HOST:PORT, ...), which gRPC
// parses itself. Refused at parse time: gRPC would wrap a port over 65535 round, and dial
// port 0 for a missing one.
CLI::Validator ServerAddress();

// The environment variable an option's long name maps to: "--max-time-s" -> "SOLTEX_MAX_TIME_S".
std::string environment_name(const std::string& long_name);

// For the programs that stream gRPC messages (soltexd, soltex-load, soltex-view), before their
// first channel or server:
// - fixed glibc malloc thresholds, so that freed memory stays in the process. By default glibc
//   serves large blocks with mmap and gives the free top of a heap back to the kernel; gRPC's
//   message and socket buffers (tens of KB, made and freed per message) then cost a page fault
//   per 4 KB on every message. These matter where the program runs on glibc's malloc: a build
//   without jemalloc (common/allocator) or a sanitizer build; with jemalloc they set an
//   allocator nothing calls;
// - no lock-order tracking in abseil's mutexes, which gRPC takes several times per message:
//   Debian's abseil tracks the order for deadlock detection on every acquisition unless told
//   not to.
void prepare_for_grpc_streams();

enum class LogStyle { plain, timestamped };

// Sends spdlog's default logger to stderr (spdlog's own default writes to stdout, where the
// tools print their results) at `level`, each line tagged with the tool's name.
void start_logging(const std::string& tool, const std::string& level,
                   LogStyle style = LogStyle::plain);

}  // namespace soltex::cli
