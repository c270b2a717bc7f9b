#pragma once

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_key.h"
#include "soltex/common/texture_spec.h"

namespace soltex::net {

// A brick the renderer wants this frame. Coarser levels are fetched first (each is the
// fallback for many finer ones), then by the screen area that needs it.
struct BrickWant {
  BrickKey key;
  uint32_t screen_pixels = 0;
};

// The order sources fetch in: coarser levels first, then more screen pixels first.
inline bool fetched_before(const BrickWant& a, const BrickWant& b) {
  if (a.key.level != b.key.level) return a.key.level > b.key.level;
  return a.screen_pixels > b.screen_pixels;
}

struct SourceStats {
  uint64_t requested = 0;  // keys asked for
  uint64_t received = 0;   // bricks that arrived in the cache
  uint64_t bytes = 0;      // encoded bytes that travelled (0 for an in-process source)
  uint64_t cancelled = 0;  // keys dropped because no frame wanted them any more
  uint64_t errors = 0;     // refused bricks, and bricks still corrupt after every refetch
  // Bricks a server refused over a queue bound of the moment and that were asked for again.
  uint64_t deferred = 0;
  uint64_t corrupt = 0;  // bricks that failed their checksum and were asked for again
  uint64_t reconnects = 0;
  // Time spent decoding arrived bricks (wall, on the receiving thread) and their decoded
  // bytes, per codec (index: Codec): what a codec costs this machine, as the link probe sees.
  double decode_seconds[3] = {0.0, 0.0, 0.0};
  uint64_t decoded_bytes[3] = {0, 0, 0};
  std::size_t in_flight = 0;
  std::size_t waiting = 0;
  bool connected = false;
};

// A server that answered and would not register one texture (its quota full, the message over
// its bound, a spec it reads otherwise): that texture alone cannot come from it. Not thrown
// for a server that cannot be reached or refuses the client itself.
class TextureRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Where a client's bricks come from: soltexd over gRPC (BrickFetcher) or an in-process
// evaluator (LocalBrickSource). Either fills the client's BrickCache in the background.
class BrickSource {
 public:
  virtual ~BrickSource() = default;

  // Registers a texture and returns its content-addressed id; throws TextureRefused, another
  // std::runtime_error or SpecError with a message naming what was refused.
  virtual uint64_t register_texture(const TextureSpec& spec, const Volume& volume, int brick_size,
                                    const MipSettings& mip) = 0;
  // This frame's misses; replaces the previous frame's wants (stale ones are cancelled).
  virtual void want(std::vector<BrickWant> wants) = 0;
  // More of the frame being drawn's misses, found before it ends (FrameRenderer::
  // set_on_tile_misses): asked for at once, after what is already waiting; nothing is
  // cancelled. The frame's want() follows with all of them. May be called from several
  // threads at once. A source that gains nothing by starting early ignores it.
  virtual void want_early(std::vector<BrickWant> /*wants*/) {}
  // While held, arriving bricks are made ready but not yet put into the cache (they stay
  // in flight), and go in together when released: a frame being drawn sees no insertions,
  // which would make every lookup it already found missing look again. Default: ignored.
  virtual void hold_arrivals(bool /*hold*/) {}
  // The codec later bricks travel in; a source that moves no bytes (in-process) ignores it.
  virtual void set_codec(Codec) {}
  // Textures the server refused after register_texture() had taken them (a stream sent them
  // again when the server's registry or the client's quota was full): each id with the
  // server's reason, once. Their bricks will not come; their objects must be evaluated here.
  virtual std::vector<std::pair<uint64_t, std::string>> take_refused_textures() { return {}; }
  virtual bool idle() const = 0;
  virtual bool wait_idle(std::chrono::milliseconds timeout) = 0;
  virtual SourceStats stats() const = 0;
};

}  // namespace soltex::net
