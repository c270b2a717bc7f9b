// The command-line conventions every tool shares, checked on the real binaries: --version,
// --help listing SOLTEX_* variables, exit 2 for any bad usage (README.md, "Exit codes"), a
// validated --log-level, options set from the environment, logs on stderr, results on stdout.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "soltexd_process.h"

#if !defined(SOLTEXD_BINARY) || !defined(SOLTEX_VIEW_BINARY) || !defined(SOLTEX_LOAD_BINARY) || \
    !defined(SOLTEX_BENCH_BINARY) || !defined(SOLTEX_GALLERY_BINARY) ||                         \
    !defined(SOLTEX_EXPECTED_VERSION) || !defined(SOLTEX_EXAMPLE_CONFIG)
#error "the five tools' paths and the project version must be defined"
#endif

extern char** environ;

namespace soltex {
namespace {

using Environment = std::vector<std::pair<std::string, std::string>>;

struct ToolRun {
  int exit_code = -1;  // -1: killed or did not finish in time
  std::string out;
  std::string err;
};

std::string file_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// In the child: the test's own SOLTEX_* variables (a developer's shell may have some) must not
// leak into a run, so only `environment` is set.
void set_child_environment(const Environment& environment) {
  std::vector<std::string> inherited;
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string text = *entry;
    if (text.rfind("SOLTEX", 0) == 0) inherited.push_back(text.substr(0, text.find('=')));
  }
  for (const std::string& name : inherited) unsetenv(name.c_str());
  for (const auto& [name, value] : environment) setenv(name.c_str(), value.c_str(), 1);
}

// A tool started with stdout and stderr in separate files under `directory`.
class ToolProcess {
 public:
  ToolProcess(const std::string& binary, std::vector<std::string> args,
              const Environment& environment, const std::filesystem::path& directory)
      : out_(directory / "stdout.txt"), err_(directory / "stderr.txt") {
    args.insert(args.begin(), binary);
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      set_child_environment(environment);
      const int out = open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int err = open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (out < 0 || err < 0) _exit(126);
      dup2(out, STDOUT_FILENO);
      dup2(err, STDERR_FILENO);
      std::vector<char*> argv;
      for (std::string& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
  }
  ~ToolProcess() { testing::kill_and_reap(pid_); }

  void signal(int number) const { kill(pid_, number); }

  // Waits up to `limit` for the exit, then kills it; the run's exit code and output.
  ToolRun finish(std::chrono::seconds limit = std::chrono::seconds(120)) {
    ToolRun run;
    const auto deadline = std::chrono::steady_clock::now() + limit;
    int status = 0;
    while (waitpid(pid_, &status, WNOHANG) != pid_) {
      if (std::chrono::steady_clock::now() > deadline) {
        testing::kill_and_reap(pid_);
        ADD_FAILURE() << "did not finish within " << limit.count() << " s";
        return run;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    pid_ = -1;
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = file_text(out_);
    run.err = file_text(err_);
    return run;
  }

 private:
  std::filesystem::path out_;
  std::filesystem::path err_;
  pid_t pid_ = -1;
};

struct Tool {
  std::string name;
  std::string binary;
  std::vector<std::string> help;  // what lists the options (soltex-bench: its subcommand's)
};

std::ostream& operator<<(std::ostream& out, const Tool& tool) {
  return out << tool.name;
}

// A scratch folder per test for the runs' output.
class ToolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    for (char& c : name) c = c == '/' ? '-' : c;
    directory_ = std::filesystem::temp_directory_path() /
                 ("soltex-cli-" + std::to_string(getpid()) + "-" + name);
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  ToolRun run_tool(const std::string& binary, const std::vector<std::string>& args,
                   const Environment& environment = {}) {
    return ToolProcess(binary, args, environment, directory_).finish();
  }

  std::filesystem::path directory_;
};

class CliConventions : public ToolTest, public ::testing::WithParamInterface<Tool> {
 protected:
  ToolRun run(const std::vector<std::string>& args, const Environment& environment = {}) {
    return run_tool(GetParam().binary, args, environment);
  }
};

TEST_P(CliConventions, VersionPrintsTheProjectVersionAndExits0) {
  const ToolRun r = run({"--version"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, GetParam().name + " " + SOLTEX_EXPECTED_VERSION + "\n");
}

TEST_P(CliConventions, HelpExits0AndNamesTheEnvironmentVariables) {
  const ToolRun r = run({"--help"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("--version"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(Env:SOLTEX_LOG_LEVEL)"), std::string::npos) << r.out;
  const ToolRun options = run(GetParam().help);
  EXPECT_EQ(options.exit_code, 0) << options.err;
  // Every option of the tool has a variable, not only --log-level.
  std::size_t count = 0;
  for (std::size_t at = options.out.find("(Env:SOLTEX_"); at != std::string::npos;
       at = options.out.find("(Env:SOLTEX_", at + 1)) {
    ++count;
  }
  EXPECT_GE(count, 3u) << options.out;
}

TEST_P(CliConventions, AnUnknownOptionExits2) {
  const ToolRun r = run({"--no-such-option"});
  EXPECT_EQ(r.exit_code, 2);
  // Named, even where a required option or subcommand is missing too.
  EXPECT_NE(r.err.find("--no-such-option"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
}

void expect_log_levels_named(const ToolRun& r) {
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("verbose"), std::string::npos) << r.err;
  for (const char* level : {"trace", "debug", "info", "warn", "error", "critical", "off"}) {
    EXPECT_NE(r.err.find(level), std::string::npos) << level << " not named in: " << r.err;
  }
}

TEST_P(CliConventions, AnUnknownLogLevelExits2NamingTheAcceptedOnes) {
  expect_log_levels_named(run({"--log-level", "verbose"}));
}

TEST_P(CliConventions, TheEnvironmentSetsTheLogLevel) {
  // Refused like the option: proof that the variable reached it. (Each tool's tests below
  // show a valid value taking effect.)
  const ToolRun from_environment = run(GetParam().help, {{"SOLTEX_LOG_LEVEL", "verbose"}});
  expect_log_levels_named(from_environment);
}

INSTANTIATE_TEST_SUITE_P(
    EveryTool, CliConventions,
    ::testing::Values(Tool{"soltexd", SOLTEXD_BINARY, {"--help"}},
                      Tool{"soltex-view", SOLTEX_VIEW_BINARY, {"--help"}},
                      Tool{"soltex-load", SOLTEX_LOAD_BINARY, {"--help"}},
                      Tool{"soltex-bench", SOLTEX_BENCH_BINARY, {"accuracy", "--help"}},
                      Tool{"soltex-gallery", SOLTEX_GALLERY_BINARY, {"--help"}}),
    [](const ::testing::TestParamInfo<Tool>& info) {
      std::string name = info.param.name;
      for (char& c : name) c = c == '-' ? '_' : c;
      return name;
    });

}  // namespace
}  // namespace soltex

namespace soltex {
namespace {

// Lines spdlog wrote at info level ("info TOOL: ..."), wherever they went.
bool has_info_line(const std::string& text, const std::string& tool) {
  return text.find("info " + tool + ":") != std::string::npos;
}

bool wait_for_file(const std::filesystem::path& path) {
  for (int i = 0; i < 400 && !std::filesystem::exists(path); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return std::filesystem::exists(path);
}

using SoltexdCli = ToolTest;

TEST_F(SoltexdCli, RunsFromTheEnvironmentAndLogsOnStderr) {
  const std::filesystem::path ready = directory_ / "ready";
  Environment environment = {{"SOLTEX_LISTEN", "127.0.0.1:0"},
                             {"SOLTEX_METRICS_LISTEN", "127.0.0.1:0"},
                             {"SOLTEX_READY_FILE", ready.string()},
                             {"SOLTEX_SHUTDOWN_GRACE_S", "0"}};
  for (const std::string level : {"info", "warn"}) {
    std::filesystem::remove(ready);
    environment.emplace_back("SOLTEX_LOG_LEVEL", level);
    ToolProcess soltexd(SOLTEXD_BINARY, {}, environment, directory_);
    ASSERT_TRUE(wait_for_file(ready)) << "soltexd did not start from SOLTEX_* alone";
    soltexd.signal(SIGTERM);
    const ToolRun r = soltexd.finish();
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out, "");  // a daemon has no results: everything it says is a log line
    EXPECT_EQ(has_info_line(r.err, "soltexd"), level == "info") << level << ": " << r.err;
    environment.pop_back();
  }
}

// A write to a log pipe whose reader went away raises SIGPIPE: soltexd ignores it and serves on.
TEST_F(SoltexdCli, ALogPipeClosingDoesNotStopIt) {
  const std::filesystem::path ready = directory_ / "ready";
  ToolProcess soltexd(SOLTEXD_BINARY,
                      {"--listen", "127.0.0.1:0", "--metrics-listen", "127.0.0.1:0", "--ready-file",
                       ready.string(), "--shutdown-grace-s", "0"},
                      {}, directory_);
  ASSERT_TRUE(wait_for_file(ready));
  soltexd.signal(SIGPIPE);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  soltexd.signal(SIGTERM);
  const ToolRun r = soltexd.finish();
  EXPECT_EQ(r.exit_code, 0) << "ended by a signal (-1) rather than by its SIGTERM: " << r.err;
}

TEST_F(SoltexdCli, TheOldEnvironmentNameStillWorks) {
  const std::filesystem::path ready = directory_ / "ready";
  ToolProcess soltexd(SOLTEXD_BINARY,
                      {"--metrics-listen", "127.0.0.1:0", "--ready-file", ready.string()},
                      {{"SOLTEXD_LISTEN", "127.0.0.1:0"}}, directory_);
  ASSERT_TRUE(wait_for_file(ready)) << "soltexd did not take SOLTEXD_LISTEN";
  soltexd.signal(SIGTERM);
  const ToolRun r = soltexd.finish();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // A line of the log like any other, with its time stamp and level.
  EXPECT_NE(r.err.find(" warning soltexd: SOLTEXD_LISTEN is deprecated; use SOLTEX_LISTEN"),
            std::string::npos)
      << r.err;
}

// The message names the option, the bound, and where the value came from when it was not
// the command line.
TEST_F(SoltexdCli, AValueFromTheEnvironmentIsValidatedLikeTheOption) {
  const ToolRun r = run_tool(SOLTEXD_BINARY, {}, {{"SOLTEX_CACHE_MB", "0"}});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--cache-mb: Value 0 not in range [1, 1048576] (from the environment "
                       "variable SOLTEX_CACHE_MB)"),
            std::string::npos)
      << r.err;
  const ToolRun word = run_tool(SOLTEXD_BINARY, {}, {{"SOLTEX_THREADS", "abc"}});
  EXPECT_EQ(word.exit_code, 2);
  EXPECT_NE(word.err.find("--threads: Value abc is not a whole number (from the environment "
                          "variable SOLTEX_THREADS)"),
            std::string::npos)
      << word.err;
}

TEST_F(SoltexdCli, AConfigFileErrorNamesTheFile) {
  const std::filesystem::path config = directory_ / "soltexd.toml";
  std::ofstream(config) << "bogus-key = 3\n";
  const ToolRun unknown = run_tool(SOLTEXD_BINARY, {"--config", config.string()});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("config file " + config.string() + ": no option is named bogus-key"),
            std::string::npos)
      << unknown.err;
  std::ofstream(config) << "cache-mb = 0\n";
  const ToolRun bound = run_tool(SOLTEXD_BINARY, {"--config", config.string()});
  EXPECT_EQ(bound.exit_code, 2);
  EXPECT_NE(bound.err.find("(from the config file " + config.string() + ")"), std::string::npos)
      << bound.err;
}

// A check across two options says where each value the command line did not give came from.
TEST_F(SoltexdCli, ACrossOptionErrorSaysWhereEachValueCameFrom) {
  const std::string message =
      "--max-keys-per-request (16) must not exceed --max-queued-per-stream (8)";
  const ToolRun r = run_tool(SOLTEXD_BINARY, {"--max-keys-per-request", "16"},
                             {{"SOLTEX_MAX_QUEUED_PER_STREAM", "8"}});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(message + " (--max-queued-per-stream from the environment variable "
                                 "SOLTEX_MAX_QUEUED_PER_STREAM)"),
            std::string::npos)
      << r.err;
  const std::filesystem::path config = directory_ / "soltexd.toml";
  std::ofstream(config) << "max-keys-per-request = 16\n";
  const ToolRun both = run_tool(SOLTEXD_BINARY, {"--config", config.string()},
                                {{"SOLTEX_MAX_QUEUED_PER_STREAM", "8"}});
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(
      both.err.find(message + " (--max-keys-per-request from the config file " + config.string() +
                    "; --max-queued-per-stream from the environment variable "
                    "SOLTEX_MAX_QUEUED_PER_STREAM)"),
      std::string::npos)
      << both.err;
  const ToolRun typed =
      run_tool(SOLTEXD_BINARY, {"--max-keys-per-request", "16", "--max-queued-per-stream", "8"});
  EXPECT_EQ(typed.exit_code, 2);
  EXPECT_NE(typed.err.find(message + "\n"), std::string::npos) << typed.err;
}

TEST_F(SoltexdCli, AnAddressOutsideHostPortExits2NamingTheBound) {
  for (const std::string option : {"--listen", "--metrics-listen", "--http-listen"}) {
    for (const std::string address : {"127.0.0.1:70000", "127.0.0.1", "127.0.0.1:-1"}) {
      const ToolRun r = run_tool(SOLTEXD_BINARY, {option, address});
      EXPECT_EQ(r.exit_code, 2) << option << " " << address << ": " << r.err;
      EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
      EXPECT_TRUE(r.err.find("[0, 65535]") != std::string::npos ||
                  r.err.find("must be HOST:PORT") != std::string::npos)
          << option << " " << address << ": " << r.err;
    }
  }
}

// Addresses that parse but name nothing usable: a memcached node on port 0, a unix socket
// without a path, a unix socket where only TCP is served.
TEST_F(SoltexdCli, AnAddressThatNamesNothingUsableExits2) {
  const struct {
    std::string option, address, says;
  } cases[] = {{"--memcached", "127.0.0.1:0", "port must be in [1, 65535]"},
               {"--listen", "unix:", "names no socket path"},
               {"--listen", "unix-abstract:", "names no socket path"},
               {"--metrics-listen", "unix:/tmp/metrics.sock", "a unix socket is not served here"},
               {"--http-listen", "unix:/tmp/http.sock", "a unix socket is not served here"}};
  for (const auto& c : cases) {
    const ToolRun r = run_tool(SOLTEXD_BINARY, {c.option, c.address});
    EXPECT_EQ(r.exit_code, 2) << c.option << " " << c.address << ": " << r.err;
    EXPECT_NE(r.err.find(c.option + ": address '" + c.address + "'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
  }
}

TEST_F(SoltexdCli, TheGrpcAddressMayBeAUnixSocket) {
  const std::filesystem::path ready = directory_ / "ready";
  const std::filesystem::path socket = directory_ / "soltexd.sock";
  ToolProcess soltexd(SOLTEXD_BINARY,
                      {"--listen", "unix:" + socket.string(), "--metrics-listen", "127.0.0.1:0",
                       "--ready-file", ready.string()},
                      {}, directory_);
  ASSERT_TRUE(wait_for_file(ready)) << "soltexd refused --listen unix:PATH";
  EXPECT_TRUE(std::filesystem::is_socket(socket));
  EXPECT_EQ(file_text(ready).substr(0, file_text(ready).find('\n')),
            "grpc=unix:" + socket.string());
  soltexd.signal(SIGTERM);
  const ToolRun r = soltexd.finish();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("listening on unix:" + socket.string() + ","), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(ready)) << "the ready file outlived the server";
}

// Field 22 of /proc/self/stat, read here as the kernel documents it (proc(5)), not through
// soltexd's own reader.
std::string process_start_ticks_of_this_test() {
  std::ifstream in("/proc/self/stat");
  std::string stat;
  std::getline(in, stat);
  std::istringstream fields(stat.substr(stat.rfind(')') + 2));
  std::string field;
  for (int i = 3; i <= 22 && (fields >> field); ++i) {
  }
  return field;
}

// A ready file left by an earlier run that is gone does not announce a server that failed to
// start.
TEST_F(SoltexdCli, AStaleReadyFileIsRemovedBeforeListening) {
  const std::filesystem::path ready = directory_ / "ready";
  std::ofstream(ready) << "grpc=1111\nmetrics=2222\n";
  testing::SoltexdProcess first;
  const std::string taken = first.grpc_address();
  const ToolRun r = run_tool(SOLTEXD_BINARY, {"--listen", taken, "--metrics-listen", "127.0.0.1:0",
                                              "--ready-file", ready.string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(ready)) << file_text(ready);
  // One that names a live process (here this test) is that process's, and stays.
  const std::string live = "grpc=1111\nmetrics=2222\npid=" + std::to_string(getpid()) + "\n";
  std::ofstream(ready) << live;
  const ToolRun again = run_tool(SOLTEXD_BINARY, {"--listen", taken, "--metrics-listen",
                                                  "127.0.0.1:0", "--ready-file", ready.string()});
  EXPECT_EQ(again.exit_code, 1) << again.err;
  EXPECT_EQ(file_text(ready), live);
  // With the start time soltexd writes too: a live pid started at another time is another
  // process that took the pid of one gone, and its file goes; the same start time stays.
  const std::string started = process_start_ticks_of_this_test();
  ASSERT_FALSE(started.empty());
  const auto start_on_the_taken_port = [&] {
    return run_tool(SOLTEXD_BINARY, {"--listen", taken, "--metrics-listen", "127.0.0.1:0",
                                     "--ready-file", ready.string()})
        .exit_code;
  };
  std::ofstream(ready) << live + "pid_start=1" + started + "\n";
  EXPECT_EQ(start_on_the_taken_port(), 1);
  EXPECT_FALSE(std::filesystem::exists(ready)) << file_text(ready);
  const std::string same = live + "pid_start=" + started + "\n";
  std::ofstream(ready) << same;
  EXPECT_EQ(start_on_the_taken_port(), 1);
  EXPECT_EQ(file_text(ready), same);
}

// A second soltexd given a running one's ready file by mistake stops before it listens,
// naming the file and its owner: it would overwrite the file, and take it away when it stops.
TEST_F(SoltexdCli, AReadyFileARunningSoltexdHoldsIsNotTaken) {
  const std::filesystem::path ready = directory_ / "ready";
  ToolProcess first(SOLTEXD_BINARY,
                    {"--listen", "127.0.0.1:0", "--metrics-listen", "127.0.0.1:0", "--ready-file",
                     ready.string()},
                    {}, directory_);
  ASSERT_TRUE(wait_for_file(ready));
  const std::string announced = file_text(ready);
  const ToolRun second = run_tool(SOLTEXD_BINARY, {"--listen", "127.0.0.1:0", "--metrics-listen",
                                                   "127.0.0.1:0", "--ready-file", ready.string()});
  EXPECT_EQ(second.exit_code, 1) << second.err;
  EXPECT_NE(second.err.find("--ready-file " + ready.string() + " belongs to the running process"),
            std::string::npos)
      << second.err;
  EXPECT_EQ(file_text(ready), announced);
  first.signal(SIGTERM);
  EXPECT_EQ(first.finish().exit_code, 0);
  EXPECT_FALSE(std::filesystem::exists(ready));
}

TEST_F(SoltexdCli, OptionsThatDoNotGoTogetherOrAFileThatDoesNotParseExit2) {
  const std::filesystem::path file = directory_ / "some.pem";
  std::ofstream(file) << "not a certificate\n";
  const std::filesystem::path tokens = directory_ / "tokens";
  std::ofstream(tokens) << "viewer-1 abc # a comment after the token\n";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--tls-cert", file.string()}, "TLS needs both --tls-cert and --tls-key"},
      {{"--tls-client-ca", file.string()}, "--tls-client-ca needs --tls-cert"},
      {{"--token-file", tokens.string()}, "line 1: expected 'NAME TOKEN' or 'TOKEN'"},
      {{"--max-keys-per-request", "100", "--max-queued-per-stream", "10"}, "must not exceed"},
      // An unset variable in a script must not turn authentication off.
      {{"--token", ""}, "--token"},
      {{"--token", "abc", "--token-file", tokens.string()}, "give one"},
      {{"--memcached", "127.0.0.1:11211,bogus"}, "must be HOST:PORT"}};
  for (const auto& [args, message] : cases) {
    const ToolRun r = run_tool(SOLTEXD_BINARY, args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
}

TEST_F(SoltexdCli, AReadyFileThatCannotBeWrittenExits1) {
  for (const std::filesystem::path& path : {directory_ / "no-such-folder" / "ready", directory_}) {
    const ToolRun r = run_tool(SOLTEXD_BINARY, {"--listen", "127.0.0.1:0", "--metrics-listen",
                                                "127.0.0.1:0", "--ready-file", path.string()});
    EXPECT_EQ(r.exit_code, 1) << path << ": " << r.err;
    EXPECT_NE(r.err.find("--ready-file"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(directory_.string() + ".tmp"));
}

TEST_F(SoltexdCli, AnEmptyMemcachedListIsOff) {
  const std::filesystem::path ready = directory_ / "ready";
  const std::filesystem::path file = directory_ / "soltexd.toml";
  std::ofstream(file) << "memcached = \"\"\n";
  ToolProcess soltexd(SOLTEXD_BINARY,
                      {"--config", file.string(), "--listen", "127.0.0.1:0", "--metrics-listen",
                       "127.0.0.1:0", "--ready-file", ready.string()},
                      {}, directory_);
  ASSERT_TRUE(wait_for_file(ready)) << "memcached = \"\" did not start";
  soltexd.signal(SIGTERM);
  const ToolRun r = soltexd.finish();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("shared brick cache"), std::string::npos) << r.err;
}

TEST_F(SoltexdCli, AConfigFileKeyItDoesNotKnowExits2) {
  // A misspelt key, a section, and a file in another format: none may be skipped silently.
  for (const std::string text :
       {"cach-mb = 1\n", "[server]\ncache-mb = 1\n", "{\"cache-mb\": 1}\n"}) {
    const std::filesystem::path file = directory_ / "soltexd.toml";
    std::ofstream(file) << text;
    const ToolRun r = run_tool(SOLTEXD_BINARY, {"--config", file.string()});
    EXPECT_EQ(r.exit_code, 2) << text << r.err;
    if (text.starts_with("[server]")) {
      EXPECT_NE(r.err.find("sections are not read ([server])"), std::string::npos) << r.err;
    }
  }
  // The same file with the key spelt right is read.
  const std::filesystem::path file = directory_ / "soltexd.toml";
  std::ofstream(file) << "cache-mb = 0\n";
  const ToolRun r = run_tool(SOLTEXD_BINARY, {"--config", file.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--cache-mb"), std::string::npos) << r.err;
}

TEST_F(SoltexdCli, TheExampleConfigFileIsReadWhole) {
  const std::filesystem::path ready = directory_ / "ready";
  ToolProcess soltexd(SOLTEXD_BINARY,
                      {"--config", SOLTEX_EXAMPLE_CONFIG, "--listen", "127.0.0.1:0",
                       "--metrics-listen", "127.0.0.1:0", "--ready-file", ready.string()},
                      {}, directory_);
  ASSERT_TRUE(wait_for_file(ready)) << "soltexd refused deploy/config/soltexd.toml";
  soltexd.signal(SIGTERM);
  const ToolRun r = soltexd.finish();
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(SoltexdCli, APortAnotherSoltexdHoldsIsRefused) {
  const std::filesystem::path ready = directory_ / "ready";
  const std::filesystem::path first_output = directory_ / "first";  // the second's is directory_
  std::filesystem::create_directories(first_output);
  ToolProcess first(SOLTEXD_BINARY,
                    {"--listen", "127.0.0.1:0", "--metrics-listen", "127.0.0.1:0", "--ready-file",
                     ready.string(), "--shutdown-grace-s", "0"},
                    {}, first_output);
  ASSERT_TRUE(wait_for_file(ready));
  const std::string text = file_text(ready);
  const std::string grpc_port = text.substr(5, text.find('\n') - 5);  // "grpc=PORT\n..."
  // Sharing the port (SO_REUSEPORT) would split new connections between the two servers.
  const ToolRun second = run_tool(
      SOLTEXD_BINARY, {"--listen", "127.0.0.1:" + grpc_port, "--metrics-listen", "127.0.0.1:0"});
  EXPECT_EQ(second.exit_code, 1) << second.err;
  EXPECT_NE(second.err.find("cannot listen for gRPC on 127.0.0.1:" + grpc_port +
                            ": Address already in use"),
            std::string::npos)
      << second.err;
  first.signal(SIGTERM);
  EXPECT_EQ(first.finish().exit_code, 0);
}

using ViewCliConventions = ToolTest;

TEST_F(ViewCliConventions, RunsFromTheEnvironmentWithResultsOnStdoutAndLogsOnStderr) {
  const std::filesystem::path png = directory_ / "view.png";
  Environment environment = {{"SOLTEX_LOCAL", "1"},        {"SOLTEX_HEADLESS", "true"},
                             {"SOLTEX_WIDTH", "32"},       {"SOLTEX_HEIGHT", "18"},
                             {"SOLTEX_OUT", png.string()}, {"SOLTEX_MAX_TIME_S", "60"}};
  const ToolRun info = run_tool(SOLTEX_VIEW_BINARY, {}, environment);
  EXPECT_EQ(info.exit_code, 0) << info.err;
  EXPECT_TRUE(std::filesystem::exists(png));
  EXPECT_NE(info.out.find("wrote:"), std::string::npos) << info.out;
  EXPECT_TRUE(has_info_line(info.err, "soltex-view")) << info.err;
  EXPECT_FALSE(has_info_line(info.out, "soltex-view")) << info.out;

  environment.emplace_back("SOLTEX_LOG_LEVEL", "warn");
  const ToolRun quiet = run_tool(SOLTEX_VIEW_BINARY, {}, environment);
  EXPECT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_FALSE(has_info_line(quiet.err, "soltex-view")) << quiet.err;
}

TEST_F(ViewCliConventions, NotANumberAndABadServerAddressExit2) {
  const std::vector<std::vector<std::string>> bad = {{"--max-time-s", "nan"},
                                                     {"--level-bias", "nan"},
                                                     {"--server", "127.0.0.1:99999"},
                                                     {"--server", "127.0.0.1"}};
  for (std::vector<std::string> args : bad) {
    const std::string option = args[0];
    args.insert(args.end(), {"--headless", "--out", (directory_ / "x.png").string()});
    const ToolRun r = run_tool(SOLTEX_VIEW_BINARY, args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << " " << args[1] << ": " << r.err;
    EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
  }
}

TEST_F(ViewCliConventions, AReferenceTooLargeToRasterizeExits2BeforeRendering) {
  const std::filesystem::path out = directory_ / "wide.png";
  const ToolRun r =
      run_tool(SOLTEX_VIEW_BINARY, {"--headless", "--local", "--width", "4097", "--height", "16",
                                    "--reference", "--supersample", "4", "--out", out.string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("give --supersample 3 or less"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out)) << "refused only after rendering";
}

TEST_F(ViewCliConventions, TheOldNameOfMaxTimeStillWorks) {
  const ToolRun r = run_tool(SOLTEX_VIEW_BINARY,
                             {"--headless", "--local", "--width", "32", "--height", "18",
                              "--max-seconds", "60", "--out", (directory_ / "v.png").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

using LoadCliConventions = ToolTest;

TEST_F(LoadCliConventions, TakesItsServerFromTheEnvironmentOrEitherName) {
  testing::SoltexdProcess soltexd;
  const std::vector<std::string> args = {"--count", "20", "--no-progress", "--format", "json"};
  const ToolRun r = run_tool(SOLTEX_LOAD_BINARY, args, {{"SOLTEX_SERVER", soltexd.grpc_address()}});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, 1), "{") << r.out;
  for (const char* name : {"--server", "--target"}) {
    std::vector<std::string> named = args;
    named.insert(named.end(), {name, soltexd.grpc_address(), "--duration-s", "30"});
    const ToolRun n = run_tool(SOLTEX_LOAD_BINARY, named);
    EXPECT_EQ(n.exit_code, 0) << name << ": " << n.err;
  }
}

// A server that goes away mid-run ends the streams UNAVAILABLE: the report is printed, and
// the exit code says the run was cut short.
TEST_F(LoadCliConventions, AServerGoneMidRunExits1) {
  testing::SoltexdProcess soltexd;
  ToolProcess load(
      SOLTEX_LOAD_BINARY,
      {"--server", soltexd.grpc_address(), "--streams", "2", "--duration-s", "30", "--no-progress"},
      {}, directory_);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_EQ(soltexd.terminate(), 0) << soltexd.log();
  const ToolRun r = load.finish();
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("of 2 ended with an error"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("streams ended with an error"), std::string::npos) << r.err;
}

TEST_F(LoadCliConventions, GrpcOnlyOptionsWithHttpExit2) {
  for (const char* option : {"--streams", "--in-flight"}) {
    const ToolRun r =
        run_tool(SOLTEX_LOAD_BINARY, {"--http", "--server", "127.0.0.1:1", option, "4"});
    EXPECT_EQ(r.exit_code, 2) << option << ": " << r.err;
    EXPECT_NE(r.err.find(std::string(option) + " does not apply to --http"), std::string::npos)
        << r.err;
  }
}

TEST_F(LoadCliConventions, WithoutAServerItExits2NamingServer) {
  const ToolRun r = run_tool(SOLTEX_LOAD_BINARY, {"--count", "1"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--server"), std::string::npos) << r.err;
}

TEST_F(LoadCliConventions, ADurationFromTheEnvironmentIsChecked) {
  const ToolRun r =
      run_tool(SOLTEX_LOAD_BINARY, {"--server", "127.0.0.1:1"}, {{"SOLTEX_DURATION_S", "0"}});
  EXPECT_EQ(r.exit_code, 2);
  // The tool's own check says where the value came from, as CLI11's checks do.
  EXPECT_NE(r.err.find("--duration-s 0: must be in (0, 3600] seconds (from the environment "
                       "variable SOLTEX_DURATION_S)"),
            std::string::npos)
      << r.err;
  const ToolRun typed =
      run_tool(SOLTEX_LOAD_BINARY, {"--server", "127.0.0.1:1", "--duration-s", "0"});
  EXPECT_EQ(typed.exit_code, 2);
  EXPECT_EQ(typed.err.find("environment"), std::string::npos) << typed.err;
}

// Two tokens typed for one run are refused; a --token-file given while SOLTEX_TOKEN is kept in
// the environment for other runs takes its place.
TEST_F(LoadCliConventions, ATokenFileTakesTheEnvironmentTokensPlaceNotATypedOnes) {
  const std::filesystem::path tokens = directory_ / "token";
  std::ofstream(tokens) << "the-right-token\n";
  testing::SoltexdProcess soltexd({"--token-file", tokens.string()});
  const std::vector<std::string> args = {
      "--server",      soltexd.grpc_address(), "--count",      "5",
      "--no-progress", "--token-file",         tokens.string()};
  std::vector<std::string> typed = args;
  typed.insert(typed.end(), {"--token", "another-token"});
  const ToolRun refused = run_tool(SOLTEX_LOAD_BINARY, typed);
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_NE(refused.err.find("--token and --token-file both name tokens: give one"),
            std::string::npos)
      << refused.err;
  const ToolRun kept = run_tool(SOLTEX_LOAD_BINARY, args, {{"SOLTEX_TOKEN", "a-stale-token"}});
  EXPECT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_NE(kept.err.find("is sent, not SOLTEX_TOKEN's"), std::string::npos) << kept.err;
  const ToolRun stale = run_tool(
      SOLTEX_LOAD_BINARY, {"--server", soltexd.grpc_address(), "--count", "5", "--no-progress"},
      {{"SOLTEX_TOKEN", "a-stale-token"}});
  EXPECT_NE(stale.exit_code, 0) << "the environment's wrong token was accepted: " << stale.err;
}

TEST_F(LoadCliConventions, AServerAddressOutsideHostPortExits2) {
  // gRPC would dial port 99999 - 65536 and port 0 without a word.
  for (const std::string address : {"127.0.0.1:99999", "127.0.0.1", ":7447", "127.0.0.1:0"}) {
    const ToolRun r = run_tool(SOLTEX_LOAD_BINARY, {"--server", address, "--count", "1"});
    EXPECT_EQ(r.exit_code, 2) << address << ": " << r.err;
    EXPECT_NE(r.err.find("--server"), std::string::npos) << r.err;
  }
}

using BenchCliConventions = ToolTest;

TEST_F(BenchCliConventions, ASubcommandOptionComesFromTheEnvironment) {
  // Refused before any measuring starts, which is what shows the variable reached the option.
  const ToolRun r =
      run_tool(SOLTEX_BENCH_BINARY, {"accuracy", "--quick", "--out-dir", directory_.string()},
               {{"SOLTEX_FRONT_CLOCK", "sundial"}});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--front-clock"), std::string::npos) << r.err;
}

TEST_F(BenchCliConventions, APlotItCannotDrawIsRefusedBeforeTheSweep) {
  const ToolRun r = run_tool(SOLTEX_BENCH_BINARY, {"accuracy", "--quick", "--out-dir",
                                                   directory_.string(), "--svg", "plot.jpg"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--svg: must end in .svg or .png"), std::string::npos) << r.err;
}

using GalleryCliConventions = ToolTest;

TEST_F(GalleryCliConventions, RunsFromTheEnvironment) {
  const std::filesystem::path out = directory_ / "gallery";
  const ToolRun r = run_tool(SOLTEX_GALLERY_BINARY, {},
                             {{"SOLTEX_SIZE", "16"}, {"SOLTEX_OUT_DIR", out.string()}});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("16 x 16"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::is_empty(out));
  const ToolRun old_name =
      run_tool(SOLTEX_GALLERY_BINARY, {"--size", "16", "--out", (directory_ / "old").string()});
  EXPECT_EQ(old_name.exit_code, 0) << old_name.err;
  EXPECT_FALSE(std::filesystem::is_empty(directory_ / "old"));
}

}  // namespace
}  // namespace soltex
