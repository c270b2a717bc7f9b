#include "soltex/cli/tool_cli.h"

#include <malloc.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cctype>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <vector>

#ifndef SOLTEX_PROJECT_VERSION
#error "SOLTEX_PROJECT_VERSION must be the CMake project version"
#endif

namespace soltex::cli {

const char* version() {
  return SOLTEX_PROJECT_VERSION;
}

void add_common_options(CLI::App& app, const std::string& tool, std::string& log_level) {
  app.set_version_flag("--version", tool + " " + version(), "print the version and exit");
  const std::vector<std::string> levels(std::begin(kLogLevels), std::end(kLogLevels));
  std::string names;
  for (const std::string& level : levels) names += (names.empty() ? "" : ", ") + level;
  app.add_option("--log-level", log_level, "log messages of this level and above: " + names)
      ->check(CLI::IsMember(levels))
      ->capture_default_str();
}

std::string environment_name(const std::string& long_name) {
  std::string name = "SOLTEX_";
  for (const char c : long_name) {
    name += c == '-' ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return name;
}

namespace {

// Help, version and the config file are not options a tool runs with: an environment variable
// for the config file would also be read too late, after CLI11 has read the file.
bool takes_environment(const CLI::App& app, const CLI::Option& option) {
  return &option != app.get_help_ptr() && &option != app.get_help_all_ptr() &&
         &option != app.get_version_ptr() && &option != app.get_config_ptr() &&
         !option.get_lnames().empty() && option.get_envname().empty();
}

void name_environment(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    if (takes_environment(app, *option)) {
      option->envname(environment_name(option->get_lnames().front()));
    }
  }
  // Option groups are nameless subcommands; real subcommands share the tool's names too.
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    name_environment(*sub);
  }
}

void adopt_deprecated(const std::string& tool, const DeprecatedEnvironmentName& names) {
  const char* old_value = std::getenv(names.old_name);
  if (old_value == nullptr) return;
  std::fprintf(stderr, "%s: %s is deprecated; use %s\n", tool.c_str(), names.old_name,
               names.new_name);
  setenv(names.new_name, old_value, /*overwrite=*/0);  // the new name wins when both are set
}

}  // namespace

std::optional<int> parse(CLI::App& app, const std::string& tool, int argc, char** argv,
                         std::initializer_list<DeprecatedEnvironmentName> deprecated) {
  name_environment(app);
  for (const DeprecatedEnvironmentName& names : deprecated) adopt_deprecated(tool, names);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // app.exit prints help or version on stdout and errors on stderr.
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  return std::nullopt;
}

void start_logging(const std::string& tool, const std::string& level, LogStyle style) {
  auto logger = spdlog::stderr_color_mt(tool);
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(level));
  spdlog::set_pattern(style == LogStyle::timestamped
                          ? "%Y-%m-%dT%H:%M:%S.%e %^%l%$ " + tool + ": %v"
                          : "%^%l%$ " + tool + ": %v");
}

void keep_freed_memory() {
  // 32 MiB is glibc's largest mmap threshold; blocks above it are rare and long-lived here.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

CLI::Validator NumberIn(double min, double max) {
  const std::string range =
      "[" + CLI::detail::to_string(min) + ", " + CLI::detail::to_string(max) + "]";
  return CLI::Validator(
      [min, max, range](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return "Value " + text + " is not a number";
        if (!(value >= min && value <= max)) return "Value " + text + " not in range " + range;
        return {};
      },
      "NUMBER in " + range);
}

CLI::Validator ServerAddress() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        for (const char* scheme : {"unix:", "unix-abstract:", "dns:", "ipv4:", "ipv6:"}) {
          if (text.starts_with(scheme)) return {};
        }
        const std::size_t colon = text.rfind(':');
        // An IPv6 host is bracketed: in "::1" the last colon is the address's own.
        const bool bare_ipv6 =
            colon != std::string::npos && text.find(':') < colon && !text.starts_with('[');
        if (colon == std::string::npos || colon == 0 || bare_ipv6) {
          return "address '" + text + "' must be HOST:PORT ([ADDRESS]:PORT for IPv6)";
        }
        unsigned port = 0;
        const char* end = text.data() + text.size();
        const auto [last, error] = std::from_chars(text.data() + colon + 1, end, port);
        if (error != std::errc() || last != end || port < 1 || port > 65535) {
          return "address '" + text + "': port must be in [1, 65535]";
        }
        return {};
      },
      "HOST:PORT");
}

}  // namespace soltex::cli
