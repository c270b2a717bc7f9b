#pragma once

#include "daemon.h"

namespace soltex::server {

// Serves until SIGINT or SIGTERM, or until the daemon fails (Daemon::on_failure); each SIGHUP
// in between reloads the TLS files and the tokens file (Daemon::reload) without touching open
// streams.
void wait_for_signals(Daemon& daemon);

}  // namespace soltex::server
