#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <unordered_set>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_layout.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/net/brick_source.h"

namespace soltex::net {

// Bricks evaluated in this process, on a background thread, exactly as soltexd makes them
// (evaluate, quantize). For running without a server, and as the reference the networked
// path must match bit for bit.
class LocalBrickSource final : public BrickSource {
 public:
  explicit LocalBrickSource(BrickCache& cache);
  ~LocalBrickSource() override;

  uint64_t register_texture(const TextureSpec& spec, const Volume& volume, int brick_size,
                            const MipSettings& mip) override;
  void want(std::vector<BrickWant> wants) override;
  bool idle() const override;
  bool wait_idle(std::chrono::milliseconds timeout) override;
  SourceStats stats() const override;

 private:
  struct Texture {
    TextureEvaluator evaluator;
    BrickLayout layout;
    MipSettings mip;
  };
  void work();

  BrickCache& cache_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::unordered_map<uint64_t, std::shared_ptr<const Texture>> textures_;
  std::vector<BrickWant> waiting_;  // best first
  std::size_t busy_ = 0;
  SourceStats stats_;
  bool stopping_ = false;
  std::thread worker_;
};

}  // namespace soltex::net
