#include "client_access.h"

#include <algorithm>
#include <string_view>

namespace soltex::server {
namespace {

constexpr std::string_view kBearer = "Bearer ";

// Compares in time independent of where the strings differ, so the token cannot be guessed
// a byte at a time from response times.
bool equal_in_constant_time(std::string_view a, std::string_view b) {
  unsigned char difference = a.size() == b.size() ? 0 : 1;
  const std::size_t n = std::max(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) {
    const auto x = static_cast<unsigned char>(i < a.size() ? a[i] : 0);
    const auto y = static_cast<unsigned char>(i < b.size() ? b[i] : 0);
    difference |= static_cast<unsigned char>(x ^ y);
  }
  return difference == 0;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// "ipv4:127.0.0.1:5000" -> "127.0.0.1", "ipv6:[::1]:5000" -> "::1", else unchanged.
std::string host_of_peer(const std::string& peer) {
  std::string_view rest = peer;
  if (const auto colon = rest.find(':');
      colon != std::string_view::npos && (rest.starts_with("ipv4:") || rest.starts_with("ipv6:"))) {
    rest.remove_prefix(colon + 1);
  } else {
    return peer;
  }
  if (rest.starts_with('[')) {
    const auto close = rest.find(']');
    return std::string(rest.substr(1, close == std::string_view::npos ? rest.npos : close - 1));
  }
  const auto port = rest.rfind(':');
  return std::string(port == std::string_view::npos ? rest : rest.substr(0, port));
}

}  // namespace

void StreamLease::release() {
  if (!released_.exchange(true)) access_.close_stream(*usage_);
}

ClientAccess::ClientAccess(AccessConfig config) : config_(std::move(config)) {}

grpc::Status ClientAccess::authenticate(const grpc::ServerContextBase& context) const {
  if (config_.token.empty()) return grpc::Status::OK;
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find("authorization");
  if (it == metadata.end()) {
    return {grpc::StatusCode::UNAUTHENTICATED,
            "this server requires a bearer token: send metadata 'authorization: Bearer <token>'"};
  }
  const std::string_view value(it->second.data(), it->second.size());
  if (!value.starts_with(kBearer)) {
    return {grpc::StatusCode::UNAUTHENTICATED,
            "the 'authorization' metadata must read 'Bearer <token>'"};
  }
  if (!equal_in_constant_time(value.substr(kBearer.size()), config_.token)) {
    return {grpc::StatusCode::UNAUTHENTICATED, "the bearer token is not valid for this server"};
  }
  return grpc::Status::OK;
}

std::string ClientAccess::client_of(const grpc::ServerContextBase& context) const {
  if (config_.trust_forwarded_for) {
    const auto& metadata = context.client_metadata();
    if (const auto it = metadata.find("x-forwarded-for"); it != metadata.end()) {
      std::string_view value(it->second.data(), it->second.size());
      value = trim(value.substr(0, value.find(',')));
      if (!value.empty()) return std::string(value);
    }
  }
  return host_of_peer(context.peer());
}

std::unique_ptr<StreamLease> ClientAccess::open_stream(const std::string& client,
                                                       grpc::Status& refusal) {
  std::lock_guard lock(mutex_);
  auto& usage = clients_[client];
  if (!usage) {
    usage = std::make_shared<ClientUsage>();
    usage->client = client;
  }
  if (usage->streams >= config_.max_streams_per_client) {
    refusal = {grpc::StatusCode::RESOURCE_EXHAUSTED,
               "client " + client + " already has " + std::to_string(usage->streams) +
                   " open brick streams; at most " +
                   std::to_string(config_.max_streams_per_client) +
                   " per client (max_streams_per_client)"};
    return nullptr;
  }
  ++usage->streams;
  return std::make_unique<StreamLease>(*this, usage);
}

void ClientAccess::close_stream(ClientUsage& usage) {
  std::lock_guard lock(mutex_);
  if (--usage.streams == 0 && usage.queued.load(std::memory_order_relaxed) == 0) {
    clients_.erase(usage.client);
  }
}

}  // namespace soltex::server
