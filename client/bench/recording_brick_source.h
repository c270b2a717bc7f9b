#pragma once

#include <mutex>
#include <unordered_set>
#include <vector>

#include "soltex/net/brick_source.h"

namespace soltex::bench {

// A BrickSource that passes everything on to another and remembers every brick a frame
// asked for: after convergence, the bricks the frame needed (what a server would have
// evaluated and sent for it).
class RecordingBrickSource final : public net::BrickSource {
 public:
  explicit RecordingBrickSource(net::BrickSource& inner) : inner_(inner) {}

  uint64_t register_texture(const TextureSpec& spec, const Volume& volume, int brick_size,
                            const MipSettings& mip) override {
    return inner_.register_texture(spec, volume, brick_size, mip);
  }
  void want(std::vector<net::BrickWant> wants) override;
  bool idle() const override { return inner_.idle(); }
  bool wait_idle(std::chrono::milliseconds timeout) override { return inner_.wait_idle(timeout); }
  net::SourceStats stats() const override { return inner_.stats(); }

  // Every key asked for so far, each once, in the order first asked.
  std::vector<BrickKey> wanted() const;

 private:
  net::BrickSource& inner_;
  mutable std::mutex mutex_;
  std::unordered_set<BrickKey, BrickKeyHash> seen_;
  std::vector<BrickKey> wanted_;
};

}  // namespace soltex::bench
