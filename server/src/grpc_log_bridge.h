#pragma once

namespace soltex::server {

// gRPC's own messages (its core logs through gpr_log, in glog's format, straight to stderr) go
// to soltexd's log instead, with its timestamps and levels: "error soltexd: gRPC: Failed
// accept4: Too many open files (tcp_server_posix.cc:205)". GRPC_VERBOSITY still decides which
// of them gRPC emits.
void route_grpc_logs_to_spdlog();

}  // namespace soltex::server
