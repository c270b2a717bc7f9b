#pragma once

#include <CLI/CLI.hpp>

#include "server_config.h"

namespace soltex::server {

// soltexd's command-line options, each bound to its field of `config`, in the groups and
// order `soltexd --help` lists them (the common options, --config among them, are the
// caller's).
void add_soltexd_options(CLI::App& app, ServerConfig& config);

}  // namespace soltex::server
