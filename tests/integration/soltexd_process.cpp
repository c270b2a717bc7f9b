#include "soltexd_process.h"

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#ifndef SOLTEXD_BINARY
#error "SOLTEXD_BINARY must name the soltexd executable"
#endif

namespace soltex::testing {
namespace {

std::string make_directory() {
  std::string pattern = (std::filesystem::temp_directory_path() / "soltexd-test-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  return pattern;
}

}  // namespace

SoltexdProcess::SoltexdProcess(std::vector<std::string> extra_args, int port, int max_descriptors)
    : directory_(make_directory()) {
  const std::string ready = directory_ + "/ready";
  const std::string log_path = directory_ + "/log";
  std::vector<std::string> args = {SOLTEXD_BINARY,
                                   "--listen",
                                   "127.0.0.1:" + std::to_string(port),
                                   "--metrics-listen",
                                   "127.0.0.1:0",
                                   "--ready-file",
                                   ready};
  // A short grace keeps tests that stop a busy server short, unless a test sets its own.
  const bool grace_given =
      std::find_if(extra_args.begin(), extra_args.end(), [](const std::string& arg) {
        return arg.rfind("--shutdown-grace", 0) == 0;
      }) != extra_args.end();
  if (!grace_given) args.insert(args.end(), {"--shutdown-grace-s", "2"});
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  pid_ = spawn_process(std::move(args), log_path, max_descriptors);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    std::ifstream in(ready);
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("grpc=", 0) == 0) grpc_port_ = std::stoi(line.substr(5));
      if (line.rfind("metrics=", 0) == 0) metrics_port_ = std::stoi(line.substr(8));
      if (line.rfind("http=", 0) == 0) http_port_ = std::stoi(line.substr(5));
    }
    if (grpc_port_ > 0 && metrics_port_ > 0) return;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      throw std::runtime_error("soltexd exited during start-up:\n" + log());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  throw std::runtime_error("soltexd did not become ready within 20 s:\n" + log());
}

SoltexdProcess::~SoltexdProcess() {
  kill_and_reap(pid_);
  std::error_code ignored;
  std::filesystem::remove_all(directory_, ignored);
}

int SoltexdProcess::terminate() {
  if (pid_ <= 0) return -1;
  kill(pid_, SIGTERM);
  return wait_for_exit(std::chrono::seconds(30));
}

int SoltexdProcess::wait_for_exit(std::chrono::milliseconds timeout) {
  if (pid_ <= 0) return -1;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return -1000;  // still running
}

void SoltexdProcess::kill_now() {
  kill_and_reap(pid_);
}

void SoltexdProcess::send_signal(int signal) {
  if (pid_ > 0) kill(pid_, signal);
}

std::string SoltexdProcess::log() const {
  std::ifstream in(directory_ + "/log");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

pid_t spawn_process(std::vector<std::string> args, const std::string& log_path,
                    int max_descriptors) {
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    if (!log_path.empty()) {
      FILE* log = std::freopen(log_path.c_str(), "w", stdout);
      if (log != nullptr) dup2(fileno(stdout), STDERR_FILENO);
    }
    if (max_descriptors > 0) {
      const rlimit limit{static_cast<rlim_t>(max_descriptors),
                         static_cast<rlim_t>(max_descriptors)};
      setrlimit(RLIMIT_NOFILE, &limit);
    }
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

void kill_and_reap(pid_t& pid) {
  if (pid <= 0) return;
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  pid = -1;
}

int free_port() {
  boost::asio::io_context io;
  boost::asio::ip::tcp::acceptor acceptor(
      io, boost::asio::ip::tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), 0));
  return acceptor.local_endpoint().port();
}

std::string http_get(int port, const std::string& path, int* status) {
  namespace beast = boost::beast;
  namespace http = beast::http;
  using tcp = boost::asio::ip::tcp;
  try {
    boost::asio::io_context io;
    tcp::socket socket(io);
    socket.connect(tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"),
                                 static_cast<unsigned short>(port)));
    http::request<http::empty_body> request(http::verb::get, path, 11);
    request.set(http::field::host, "127.0.0.1");
    http::write(socket, request);
    beast::flat_buffer buffer;
    http::response<http::string_body> response;
    http::read(socket, buffer, response);
    if (status) *status = static_cast<int>(response.result_int());
    return response.body();
  } catch (const std::exception&) {
    if (status) *status = 0;
    return "";
  }
}

double metric_value(const std::string& exposition, const std::string& name) {
  std::istringstream in(exposition);
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() > name.size() && line.compare(0, name.size(), name) == 0 &&
        line[name.size()] == ' ') {
      return std::strtod(line.c_str() + name.size() + 1, nullptr);
    }
  }
  return -1.0;
}

}  // namespace soltex::testing
