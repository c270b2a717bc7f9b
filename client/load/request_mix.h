#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "load_options.h"
#include "request_log.h"
#include "soltex/common/brick_key.h"

// Which bricks a load run asks for: one RequestMix per stream, each with its own random
// sequence, all drawing from the same key population.
namespace soltex::load {

// The registered texture's brick pyramid, from its TextureHandle.
struct TextureShape {
  uint64_t texture_id = 0;
  int level_count = 1;  // levels 0 (finest) .. level_count - 1 (a single brick)
  int brick_size = 16;

  int bricks_per_axis(int level) const { return 1 << (level_count - 1 - level); }
  uint64_t brick_count() const;  // over all levels
};

// Requests the server must refuse, to exercise its per-brick errors.
enum class InvalidKind { none, out_of_range, unknown_texture };

struct PlannedWant {
  BrickKey key;
  int32_t priority = 0;
  InvalidKind invalid = InvalidKind::none;
};

struct MixSettings {
  MixKind kind = MixKind::hot;
  int hot_set = 64;
  std::vector<RecordedRequest> replay;  // for MixKind::replay; must not be empty
  double invalid_fraction = 0.0;
  uint64_t seed = 1;
};

class RequestMix {
 public:
  virtual ~RequestMix() = default;

  // True when the stream already waits for `key`. The server keeps a key at most once in a
  // stream's queue, so a repeat could be merged into the first and answered once; mixes that
  // choose freely avoid busy keys (a few redraws), replay does not choose and keeps its order.
  using Busy = std::function<bool(const BrickKey&)>;

  virtual PlannedWant next(const Busy& busy) = 0;
};

// One mix per stream. Hot: `hot_set` distinct keys drawn once (the same for every stream),
// each request one of them at random. Uniform: every brick of every level equally likely, so
// the fine levels, which hold most bricks, dominate. Replay: stream s of S plays requests
// s, s + S, s + 2S, ... of the log, from the start again when it runs out. On top of any
// mix, `invalid_fraction` of the requests are replaced by invalid keys, alternately out of
// range and of an unknown texture.
std::vector<std::unique_ptr<RequestMix>> make_request_mixes(const MixSettings& settings,
                                                            const TextureShape& shape, int streams);

}  // namespace soltex::load
