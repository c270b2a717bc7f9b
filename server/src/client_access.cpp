#include "client_access.h"

#include <algorithm>
#include <boost/beast/core/string.hpp>
#include <stdexcept>
#include <string_view>

namespace soltex::server {
namespace {

constexpr std::string_view kBearer = "bearer ";  // compared without case
constexpr std::string_view kForwardedFor = "x-forwarded-for";

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

bool trusted(const std::vector<AddressRange>& proxies, const IpAddress& address) {
  return std::any_of(proxies.begin(), proxies.end(),
                     [&](const AddressRange& range) { return range.contains(address); });
}

// Every comma-separated entry of every x-forwarded-for header, in order (client first).
std::vector<std::string_view> forwarded_entries(const grpc::ServerContextBase& context) {
  std::vector<std::string_view> entries;
  const auto [begin, end] = context.client_metadata().equal_range(kForwardedFor.data());
  for (auto it = begin; it != end; ++it) {
    std::string_view value(it->second.data(), it->second.size());
    while (!value.empty()) {
      const auto comma = value.find(',');
      entries.push_back(trim(value.substr(0, comma)));
      value.remove_prefix(comma == std::string_view::npos ? value.size() : comma + 1);
    }
  }
  return entries;
}

}  // namespace

void StreamLease::release() {
  if (!released_.exchange(true)) access_.close_stream(*usage_);
}

ClientAccess::ClientAccess(AccessConfig config)
    : config_(std::move(config)),
      token_required_(!config_.tokens.empty()),
      tokens_(std::make_shared<const std::vector<AccessToken>>(config_.tokens)) {}

std::shared_ptr<const std::vector<AccessToken>> ClientAccess::tokens() const {
  std::lock_guard lock(tokens_mutex_);
  return tokens_;
}

void ClientAccess::replace_tokens(std::vector<AccessToken> tokens) {
  if (token_required_ && tokens.empty()) {
    throw std::invalid_argument("a reload may not remove every token (restart without one)");
  }
  auto next = std::make_shared<const std::vector<AccessToken>>(std::move(tokens));
  std::lock_guard lock(tokens_mutex_);
  tokens_ = std::move(next);
}

grpc::Status ClientAccess::identify(const grpc::ServerContextBase& context,
                                    std::string& client) const {
  client = address_of(context);
  if (!token_required_) return grpc::Status::OK;
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find("authorization");
  if (it == metadata.end()) return check_token(nullptr, client);
  const std::string_view value(it->second.data(), it->second.size());
  return check_token(&value, client);
}

grpc::Status ClientAccess::check_token(const std::string_view* authorization,
                                       std::string& client) const {
  if (!token_required_) return grpc::Status::OK;
  if (authorization == nullptr) {
    return {grpc::StatusCode::UNAUTHENTICATED,
            "this server requires a bearer token: send metadata 'authorization: Bearer <token>'"};
  }
  std::string_view value = *authorization;
  // The scheme's name is case-insensitive (RFC 9110 11.1), and spaces may follow it.
  const bool bearer =
      value.size() > kBearer.size() &&
      boost::beast::iequals({value.data(), kBearer.size()}, {kBearer.data(), kBearer.size()});
  if (!bearer) {
    return {grpc::StatusCode::UNAUTHENTICATED,
            "the 'authorization' metadata must read 'Bearer <token>'"};
  }
  value.remove_prefix(kBearer.size());
  while (!value.empty() && value.front() == ' ') value.remove_prefix(1);
  const std::string_view presented = value;
  const AccessToken* match = nullptr;
  // Every token is compared, so the time taken tells nothing about which one matched.
  for (const AccessToken& token : *tokens()) {
    if (equal_in_constant_time(presented, token.secret) && match == nullptr) match = &token;
  }
  if (match == nullptr) {
    return {grpc::StatusCode::UNAUTHENTICATED, "the bearer token is not valid for this server"};
  }
  if (!match->name.empty()) client = "token:" + match->name;
  return grpc::Status::OK;
}

std::string ClientAccess::address_of(const std::string& peer_host,
                                     const std::vector<std::string_view>& forwarded) const {
  if (config_.trusted_proxies.empty()) return peer_host;
  std::vector<std::string_view> entries;
  for (std::string_view value : forwarded) {
    while (!value.empty()) {
      const auto comma = value.find(',');
      entries.push_back(trim(value.substr(0, comma)));
      value.remove_prefix(comma == std::string_view::npos ? value.size() : comma + 1);
    }
  }
  return client_address(peer_host, entries, config_.trusted_proxies);
}

std::string ClientAccess::address_of(const grpc::ServerContextBase& context) const {
  const std::string peer = host_of_peer(context.peer());
  if (config_.trusted_proxies.empty()) return peer;
  return client_address(peer, forwarded_entries(context), config_.trusted_proxies);
}

std::string client_address(const std::string& peer_host,
                           const std::vector<std::string_view>& forwarded,
                           const std::vector<AddressRange>& trusted_proxies) {
  const std::optional<IpAddress> peer = IpAddress::parse(peer_host);
  if (!peer || !trusted(trusted_proxies, *peer)) return peer_host;
  // Walking from the right, each trusted proxy added the address it saw; what the client
  // itself sent (and could forge) lies further left.
  for (auto it = forwarded.rbegin(); it != forwarded.rend(); ++it) {
    const std::optional<IpAddress> address = IpAddress::parse(*it);
    if (!address) break;
    if (!trusted(trusted_proxies, *address) || std::next(it) == forwarded.rend()) {
      return std::string(*it);
    }
  }
  return peer_host;
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
