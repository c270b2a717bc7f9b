#include "soltex/cli/tool_cli.h"

#include <absl/synchronization/mutex.h>
#include <malloc.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cctype>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <string_view>
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

// Warnings found while parsing, before the log exists: start_logging() writes them in the
// log's own format, or parse() to stderr when the tool stops before it logs.
std::vector<std::string>& warnings_before_logging() {
  static std::vector<std::string> warnings;
  return warnings;
}

void print_warnings_before_logging(const std::string& tool) {
  for (const std::string& warning : warnings_before_logging()) {
    std::fprintf(stderr, "%s: %s\n", tool.c_str(), warning.c_str());
  }
  warnings_before_logging().clear();
}

void adopt_deprecated(const DeprecatedEnvironmentName& names) {
  const char* old_value = std::getenv(names.old_name);
  if (old_value == nullptr) return;
  warnings_before_logging().push_back(std::string(names.old_name) + " is deprecated; use " +
                                      names.new_name);
  setenv(names.new_name, old_value, /*overwrite=*/0);  // the new name wins when both are set
}

// Every option of the tool and of its subcommands and option groups.
void collect_options(const CLI::App& app, std::vector<const CLI::Option*>& options) {
  for (const CLI::Option* option : app.get_options()) options.push_back(option);
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    collect_options(*sub, options);
  }
}

// Whether a CLI11 message is about `option` ("--name: ...").
// CLI11 writes "--name: ...", the tools' own checks "--name VALUE: ...".
bool message_names(const std::string& message, const CLI::Option& option) {
  for (const std::string& name : option.get_lnames()) {
    if (message.rfind("--" + name + ":", 0) == 0 || message.rfind("--" + name + " ", 0) == 0) {
      return true;
    }
  }
  return false;
}

std::string config_file_of(const CLI::App& app) {
  const CLI::Option* config = app.get_config_ptr();
  return config != nullptr && config->count() > 0 ? config->as<std::string>() : std::string();
}

// CLI11's message with what it leaves out: the config file an unknown key is in, and where a
// refused value came from when the command line did not give it.
std::string with_source(const CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
  const std::string message = error.what();
  const std::string config_file = config_file_of(app);
  constexpr std::string_view kUnknownKey = "INI was not able to parse ";
  if (message.rfind(kUnknownKey, 0) == 0) {
    const std::string key = message.substr(kUnknownKey.size());
    // CLI11 names the start of a [section] "section.++", and a key in it "section.key".
    if (key.size() > 3 && key.ends_with(".++")) {
      return "config file " + config_file + ": sections are not read ([" +
             key.substr(0, key.size() - 3) +
             "]): write every option as a top-level key, before any [section] line";
    }
    return "config file " + config_file + ": no option is named " + key;
  }
  return with_value_source(app, message, argc, argv);
}

// The option's environment variable when it is set (CLI11 leaves an empty one unread), else
// nullptr.
const char* set_variable(const CLI::Option& option) {
  const std::string& variable = option.get_envname();
  const char* set = variable.empty() ? nullptr : std::getenv(variable.c_str());
  return set != nullptr && *set != '\0' ? set : nullptr;
}

// Whether the option holds its set variable's value. CLI11 reads a config file's value over
// the environment's: a value unlike the variable's came from the file, and one like it may be
// taken as the variable's.
bool holds_variable(const CLI::Option& option, const char* set) {
  const std::vector<std::string>& results = option.results();
  return set != nullptr && results.size() == 1 && results.front() == set;
}

// Where `option`'s value came from when the command line did not give it: "from the
// environment variable X", "from the config file F", or "".
std::string value_source(const CLI::Option& option, const std::string& config_file) {
  const char* set = set_variable(option);
  if (set != nullptr && (config_file.empty() || holds_variable(option, set))) {
    return "from the environment variable " + option.get_envname();
  }
  if (!config_file.empty() && option.count() > 0) return "from the config file " + config_file;
  return {};
}

// "--name" when `message` names `option` after its start as a whole word (not the prefix of a
// longer option's name), or "".
std::string named_later(const std::string& message, const CLI::Option& option) {
  const auto name_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_';
  };
  for (const std::string& name : option.get_lnames()) {
    const std::string flag = "--" + name;
    for (std::size_t at = message.find(flag, 1); at != std::string::npos;
         at = message.find(flag, at + 1)) {
      const std::size_t end = at + flag.size();
      if (!name_char(message[at - 1]) && (end == message.size() || !name_char(message[end]))) {
        return flag;
      }
    }
  }
  return {};
}

}  // namespace

std::string with_value_source(const CLI::App& app, const std::string& message, int argc,
                              char** argv) {
  const std::string config_file = config_file_of(app);
  std::vector<const CLI::Option*> options;
  collect_options(app, options);
  // The option the message is about, named first, gets "(from ...)"; others it names further
  // on ("--a (8) must not exceed --b (4)") get "--b from ..." in the same parentheses.
  std::string subject_source;
  std::vector<std::string> others;
  for (const CLI::Option* option : options) {
    if (on_command_line(*option, argc, argv)) continue;
    if (message_names(message, *option)) {
      subject_source = value_source(*option, config_file);
    } else if (const std::string name = named_later(message, *option); !name.empty()) {
      if (const std::string source = value_source(*option, config_file); !source.empty()) {
        others.push_back(name + " " + source);
      }
    }
  }
  if (others.empty())
    return subject_source.empty() ? message : message + " (" + subject_source + ")";
  std::string note = subject_source.empty() ? ""
                                            : message.substr(0, message.find_first_of(" :")) + " " +
                                                  subject_source + "; ";
  for (std::size_t i = 0; i < others.size(); ++i) note += (i > 0 ? "; " : "") + others[i];
  return message + " (" + note + ")";
}

bool value_from_environment(const CLI::Option& option, int argc, char** argv) {
  return holds_variable(option, set_variable(option)) && !on_command_line(option, argc, argv);
}

bool on_command_line(const CLI::Option& option, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    for (const std::string& name : option.get_lnames()) {
      const std::string flag = "--" + name;
      if (arg == flag || arg.rfind(flag + "=", 0) == 0) return true;
    }
  }
  return false;
}

namespace {

// Whether `app` or one of its subcommands (at any depth) has the option `name` ("--x", "-x").
bool knows_option(const CLI::App& app, const std::string& name) {
  if (app.get_option_no_throw(name) != nullptr) return true;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (knows_option(*sub, name)) return true;
  }
  return false;
}

// The first argument no part of `app` knows: an option none has, or a word where a
// subcommand is expected and none is named so. CLI11 reports a missing required option or
// subcommand before an unknown one, which names the wrong mistake.
std::optional<std::string> unknown_argument(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") break;
    const bool number = arg.size() > 1 && (std::isdigit(static_cast<unsigned char>(arg[1])) ||
                                           arg[1] == '.');  // -5, -.5: a value, not an option
    if (arg.size() > 1 && arg[0] == '-' && !number) {
      // --name=value, or -x with its value run on (-j4).
      const std::string name = arg[1] == '-' ? arg.substr(0, arg.find('=')) : arg.substr(0, 2);
      if (!knows_option(app, name)) return name;
    } else if (i == 1 && app.get_require_subcommand_min() > 0) {
      const auto named = app.get_subcommands(
          [&arg](const CLI::App* sub) { return const_cast<CLI::App*>(sub)->check_name(arg); });
      if (named.empty()) return arg;
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<int> parse(CLI::App& app, const std::string& tool, int argc, char** argv,
                         std::initializer_list<DeprecatedEnvironmentName> deprecated) {
  name_environment(app);
  for (const DeprecatedEnvironmentName& names : deprecated) adopt_deprecated(names);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    print_warnings_before_logging(tool);
    // Help and version: app.exit prints them on stdout.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
      return app.exit(e) == 0 ? kExitOk : kExitUsage;
    }
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
      if (const auto unknown = unknown_argument(app, argc, argv)) {
        std::fprintf(stderr, "%s: unknown %s %s\nRun with --help for more information.\n",
                     tool.c_str(), (*unknown)[0] == '-' ? "option" : "subcommand",
                     unknown->c_str());
        return kExitUsage;
      }
    }
    std::fprintf(stderr, "%s\nRun with --help for more information.\n",
                 with_source(app, e, argc, argv).c_str());
    return kExitUsage;
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
  for (const std::string& warning : warnings_before_logging()) spdlog::warn("{}", warning);
  warnings_before_logging().clear();
}

void prepare_for_grpc_streams() {
  // 32 MiB is glibc's largest mmap threshold; blocks above it are rare and long-lived here.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
}

CLI::Validator IntegerIn(long long min, long long max) {
  const std::string range = "[" + std::to_string(min) + ", " + std::to_string(max) + "]";
  return CLI::Validator(
      [min, max, range](std::string& text) -> std::string {
        long long value = 0;
        const char* end = text.data() + text.size();
        const auto [stop, error] = std::from_chars(text.data(), end, value);
        if (text.empty() || stop != end || error == std::errc::invalid_argument) {
          return "Value " + text + " is not a whole number";
        }
        if (error == std::errc::result_out_of_range || value < min || value > max) {
          return "Value " + text + " not in range " + range;
        }
        return {};
      },
      "INTEGER in " + range);
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
