#include "brick_service.h"

#include <spdlog/spdlog.h>

#include "texture_registration.h"

namespace soltex::server {
namespace {

// A stream refused before it starts (no token, too many streams): finishes at once.
class RefusedStream final : public BrickStream::ServerReactor {
 public:
  explicit RefusedStream(const grpc::Status& status) { Finish(status); }
  void OnDone() override { delete this; }
};

// `bytes` as a `Message`, or INVALID_ARGUMENT naming the type it is not.
template <typename Message>
grpc::Status parse_request(const grpc::ByteBuffer& bytes, Message& message) {
  grpc::ByteBuffer copy(bytes);  // shares the slices: Deserialize consumes its buffer
  const grpc::Status parsed = grpc::SerializationTraits<Message>::Deserialize(&copy, &message);
  if (parsed.ok()) return parsed;
  return {grpc::StatusCode::INVALID_ARGUMENT, "request message is not a " +
                                                  Message::descriptor()->full_name() + " (" +
                                                  parsed.error_message() + ")"};
}

void write_response(const google::protobuf::Message& message, grpc::ByteBuffer& bytes) {
  bool own_buffer = false;
  (void)grpc::SerializationTraits<google::protobuf::Message>::Serialize(message, &bytes,
                                                                        &own_buffer);
}

}  // namespace

BrickServiceImpl::BrickServiceImpl(BrickStream::Context context, ClientAccess& access,
                                   v1::ServerInfo info)
    : context_(context), access_(access), info_(std::move(info)) {}

grpc::Status BrickServiceImpl::admit(const grpc::CallbackServerContext& context,
                                     std::string& client) {
  grpc::Status status = access_.identify(context, client);
  if (!status.ok()) {
    context_.metrics.count_error(static_cast<int>(status.error_code()));
    context_.refusals.refused(client, "call from " + client + " (peer " + context.peer() +
                                          ") refused: " + status.error_message());
  }
  return status;
}

grpc::ServerUnaryReactor* BrickServiceImpl::GetServerInfo(grpc::CallbackServerContext* context,
                                                          const grpc::ByteBuffer* request,
                                                          grpc::ByteBuffer* response) {
  auto* reactor = context->DefaultReactor();
  std::string client;
  grpc::Status status = admit(*context, client);
  v1::GetServerInfoRequest parsed;
  if (status.ok()) status = parse_request(*request, parsed);
  if (status.ok()) write_response(info_, *response);
  reactor->Finish(status);
  return reactor;
}

grpc::ServerUnaryReactor* BrickServiceImpl::RegisterTexture(grpc::CallbackServerContext* context,
                                                            const grpc::ByteBuffer* request,
                                                            grpc::ByteBuffer* response) {
  auto* reactor = context->DefaultReactor();
  std::string client;
  if (grpc::Status admitted = admit(*context, client); !admitted.ok()) {
    reactor->Finish(admitted);
    return reactor;
  }
  context_.metrics.register_requests.fetch_add(1, std::memory_order_relaxed);
  v1::RegisterTextureRequest parsed;
  if (grpc::Status status = parse_request(*request, parsed); !status.ok()) {
    context_.metrics.count_error(static_cast<int>(status.error_code()));
    reactor->Finish(status);
    return reactor;
  }
  try {
    // Not used by a stream yet: the pin goes at once and the texture is the most recent.
    write_response(texture_handle(*register_texture(context_.registry, parsed, client).texture()),
                   *response);
  } catch (const RegistrationError& e) {
    context_.metrics.count_error(static_cast<int>(e.code()));
    if (e.code() == grpc::StatusCode::RESOURCE_EXHAUSTED) {
      context_.refusals.refused(client, "RegisterTexture from " + client + " refused: " + e.what());
    } else {
      spdlog::debug("RegisterTexture from {} refused: {}", client, e.what());
    }
    reactor->Finish(grpc::Status(e.code(), e.what()));
    return reactor;
  }
  reactor->Finish(grpc::Status::OK);
  return reactor;
}

BrickStream::ServerReactor* BrickServiceImpl::StreamBricks(grpc::CallbackServerContext* context) {
  std::string client;
  if (grpc::Status admitted = admit(*context, client); !admitted.ok()) {
    return new RefusedStream(admitted);
  }
  grpc::Status refusal;
  std::unique_ptr<StreamLease> lease = access_.open_stream(client, refusal);
  if (!lease) {
    context_.metrics.count_error(static_cast<int>(refusal.error_code()));
    context_.refusals.refused(client, "stream from " + client + " (peer " + context->peer() +
                                          ") refused: " + refusal.error_message());
    return new RefusedStream(refusal);
  }
  const uint64_t id = next_stream_id_.fetch_add(1, std::memory_order_relaxed);
  auto stream = std::make_shared<BrickStream>(
      context_, id, client + " (peer " + context->peer() + ")", std::move(lease));
  {
    std::lock_guard lock(streams_mutex_);
    // Forget streams that have ended, so the map stays the size of the open ones.
    std::erase_if(streams_, [](const auto& entry) { return entry.second.expired(); });
    streams_.emplace(id, stream);
    // Opened as shutdown began (gRPC may still hand over a call it had accepted): drained
    // like the others, so it ends once it owes nothing rather than at the grace's end.
    if (draining_) stream->drain();
  }
  return stream->start();
}

std::vector<std::shared_ptr<BrickStream>> BrickServiceImpl::open_streams() {
  std::vector<std::shared_ptr<BrickStream>> open;
  std::lock_guard lock(streams_mutex_);
  for (const auto& [id, weak] : streams_) {
    if (auto stream = weak.lock()) open.push_back(std::move(stream));
  }
  return open;
}

void BrickServiceImpl::drain_streams() {
  {
    std::lock_guard lock(streams_mutex_);
    draining_ = true;
  }
  for (const auto& stream : open_streams()) stream->drain();
}

void BrickServiceImpl::shut_down_streams() {
  for (const auto& stream : open_streams()) stream->shut_down();
}

}  // namespace soltex::server
