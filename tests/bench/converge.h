#pragma once

#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>

#include "soltex/net/local_brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/prepared_scene.h"

// Draws frames of `prepared` until every brick they want is resident and `source` is idle, so
// that the benchmark times warm frames only. Throws std::runtime_error, naming `bench`, when the
// scene has not converged after 120 s.
inline void converge(soltex::FrameRenderer& renderer, const soltex::PreparedScene& prepared,
                     const soltex::Camera& camera, int width, int height,
                     soltex::net::LocalBrickSource& source, const std::string& bench) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  for (;;) {
    soltex::Frame frame = renderer.render(prepared, camera, width, height);
    const bool complete = frame.complete();
    source.want(std::move(frame.misses));
    if (complete && source.idle()) break;
    if (std::chrono::steady_clock::now() > deadline) {
      throw std::runtime_error(bench + ": the scene did not converge in 120 s");
    }
    source.wait_idle(std::chrono::milliseconds(50));
  }
}
