#pragma once

#include <CLI/CLI.hpp>

#include "server_config.h"

namespace soltex::server {

// soltexd's command-line options, each bound to its field of `config`, in the groups and
// order `soltexd --help` lists them (the common options, --config among them, are the
// caller's).
void add_soltexd_options(CLI::App& app, ServerConfig& config);

// What makes a parsed command line unusable as a whole, for exit 2 before anything starts:
// options that need each other, a removed option, a tokens file or proxy list that does not
// parse. Empty when there is nothing (the daemon checks the same again, for other callers).
std::string usage_problem(const ServerConfig& config);

}  // namespace soltex::server
