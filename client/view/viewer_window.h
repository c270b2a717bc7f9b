#pragma once

#include <filesystem>
#include <memory>
#include <stdexcept>

#include "level_bias_controller.h"
#include "soltex/common/brick_cache.h"
#include "soltex/net/brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/image.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/scene.h"

namespace soltex::view {

// No window could be opened (no display, no video driver): SDL's message.
class WindowUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ViewerSettings {
  int width = 1280;  // the frame the renderer draws; the window scales it to its own size
  int height = 720;
  int max_frames = 0;                // close after this many frames; 0: when the user quits
  std::filesystem::path screenshot;  // the last frame is written here on close; empty: not
  bool adaptive_level_bias = true;
  LevelBiasSettings level_bias;
  // The capability's start (level_cap.h): while the view moves, no texture is fetched finer
  // than 2^start_level_log2; a still view refines one level at a time to the prepared levels,
  // as far as the cache budget holds them. 0: no cap.
  int start_level_log2 = 0;
};

struct ViewerResult {
  int frames = 0;
  double first_frame_ms = 0.0;  // from run() to the first frame shown
  Image last_image;             // what the window showed last
};

// The interactive window of soltex-view. Every frame is drawn at once from what the brick
// cache holds and its misses go to the brick source, which fills the cache in the background;
// later frames refine. Frames are drawn only while something changes (input, arriving
// bricks, the scene's camera.orbit turntable, refining), so a converged, untouched view
// costs nothing. A scene with camera.orbit turns for its frames at the start (turntable.h).
//
//   left drag        orbit the camera around its target
//   wheel            zoom
//   1..9, Tab        the object under the cursor (all objects when the cursor is over the
//                    background, or with Shift held) takes lecture texture N, or the next one
//                    (Shift+Tab: the previous); 0 gives back the scene's own textures
//   Up/Down          move the clip planes along their normals (PageUp/PageDown: faster)
//   L                false-colour levels
//   F                texture filter: nearest, trilinear, quadrilinear
//   A                adaptive level bias on/off
//   R                camera back to the scene's (and the scene's orbit plays again)
//   Esc, Q           quit
class ViewerWindow {
 public:
  // Opens the window and prepares a copy of the scene (the window changes its textures and
  // clip planes). Throws WindowUnavailable when no window can be opened (e.g. no display),
  // and what prepare_scene throws. `cache` and `source` must outlive the window.
  ViewerWindow(Scene scene, const TextureResolution& resolution, BrickCache& cache,
               net::BrickSource& source, const RenderOptions& options,
               const ViewerSettings& settings);
  ~ViewerWindow();

  ViewerWindow(const ViewerWindow&) = delete;
  ViewerWindow& operator=(const ViewerWindow&) = delete;

  // Draws and handles input until the user quits or max_frames are drawn, then writes the
  // screenshot if one was asked for (throws std::runtime_error if that fails).
  ViewerResult run();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace soltex::view
