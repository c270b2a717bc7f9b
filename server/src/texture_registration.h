#pragma once

#include <grpcpp/grpcpp.h>

#include <stdexcept>
#include <string>

#include "soltex/v1/brick_service.pb.h"
#include "texture_registry.h"

namespace soltex::server {

// A registration the server refuses: the gRPC code to answer with and a message naming the
// field and the bound it broke.
class RegistrationError : public std::runtime_error {
 public:
  RegistrationError(grpc::StatusCode code, const std::string& message)
      : std::runtime_error(message), code_(code) {}
  grpc::StatusCode code() const { return code_; }

 private:
  grpc::StatusCode code_;
};

// Validates and registers one texture for `client`, whether it came as a RegisterTexture call
// or inside a stream's BrickRequest, and returns it pinned. Throws RegistrationError.
TexturePin register_texture(TextureRegistry& registry, const v1::RegisterTextureRequest& request,
                            const std::string& client, const TextureRegistry::Check& check = {});

// The id register_texture() would give the texture, without registering it (or checking more
// than the id needs). Throws RegistrationError.
uint64_t registration_id(const v1::RegisterTextureRequest& request);

// What the client learns about a registered texture.
v1::TextureHandle texture_handle(const RegisteredTexture& texture);

}  // namespace soltex::server
