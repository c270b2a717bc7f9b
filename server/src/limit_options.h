#pragma once

#include <CLI/CLI.hpp>

#include "daemon.h"
#include "server_config.h"

namespace soltex::server {

// soltexd's options for the texture registry's bounds and for who a client is
// (--registry-mb, --max-textures-per-client, --trusted-proxies), in the `security` group.
void add_limit_options(CLI::Option_group& security, ServerConfig& config);

// Serves until SIGINT or SIGTERM; each SIGHUP in between reloads the TLS files and the
// tokens file (Daemon::reload) without touching open streams.
void wait_for_signals(Daemon& daemon);

}  // namespace soltex::server
