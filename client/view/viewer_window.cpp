#include "viewer_window.h"

// soltex-view has its own main(); SDL must not replace it.
#define SDL_MAIN_HANDLED
#include <SDL.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <climits>
#include <cstdlib>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "lecture_textures.h"
#include "level_cap.h"
#include "object_picker.h"
#include "orbit_controller.h"
#include "refused_textures.h"
#include "turntable.h"
#include "view_setup.h"
#include "window_title.h"

namespace soltex::view {
namespace {

using Clock = std::chrono::steady_clock;

constexpr auto kTitleInterval = std::chrono::milliseconds(250);
// Input this recent still counts as interacting: between two mouse events of one drag the
// adaptive level bias must not fall back to full detail.
constexpr auto kInteractionHold = std::chrono::milliseconds(300);
// How long to sleep in the event queue while nothing changes; short, so arriving bricks show.
constexpr int kIdleWaitMs = 15;
constexpr double kOrbitDegreesPerPixel = 0.4;
// Clip planes move by this share of the camera's distance per key press, so the step suits
// the scene's scale.
constexpr double kClipStepPerDistance = 0.02;
constexpr double kFastClipStepFactor = 5.0;

double ms_between(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

WindowUnavailable sdl_error(const std::string& what) {
  return WindowUnavailable(what + ": " + SDL_GetError());
}

struct SdlDestroy {
  void operator()(SDL_Window* window) const { SDL_DestroyWindow(window); }
  void operator()(SDL_Renderer* renderer) const { SDL_DestroyRenderer(renderer); }
  void operator()(SDL_Texture* texture) const { SDL_DestroyTexture(texture); }
};

// SDL's video subsystem for the lifetime of a window.
class SdlVideo {
 public:
  SdlVideo() {
    SDL_SetMainReady();
    if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) throw sdl_error("cannot start SDL video");
    // Without a display SDL falls back to drivers that show nothing; a window nobody can
    // see or close would run forever. They stay available when asked for by name.
    const std::string driver = SDL_GetCurrentVideoDriver();
    const char* asked = std::getenv("SDL_VIDEODRIVER");
    if ((driver == "offscreen" || driver == "dummy") && (asked == nullptr || driver != asked)) {
      SDL_QuitSubSystem(SDL_INIT_VIDEO);
      throw WindowUnavailable("no display to open a window on (SDL found only its '" + driver +
                              "' video driver)");
    }
  }
  ~SdlVideo() { SDL_QuitSubSystem(SDL_INIT_VIDEO); }
  SdlVideo(const SdlVideo&) = delete;
  SdlVideo& operator=(const SdlVideo&) = delete;
};

SampleFilter next_filter(SampleFilter filter) {
  switch (filter) {
    case SampleFilter::nearest:
      return SampleFilter::trilinear;
    case SampleFilter::trilinear:
      return SampleFilter::quadrilinear;
    case SampleFilter::quadrilinear:
      return SampleFilter::nearest;
  }
  return SampleFilter::trilinear;
}

// 1..9 on the main row or the keypad: the lecture texture index 0..8.
std::optional<int> texture_key(SDL_Keycode key) {
  if (key >= SDLK_1 && key <= SDLK_9) return static_cast<int>(key - SDLK_1);
  // The keypad's digits are consecutive scancodes, so their keycodes are too.
  if (key >= SDLK_KP_1 && key <= SDLK_KP_9) return static_cast<int>(key - SDLK_KP_1);
  return std::nullopt;
}

}  // namespace

struct ViewerWindow::Impl {
  Impl(Scene scene_to_show, const TextureResolution& texture_resolution, BrickCache& brick_cache,
       net::BrickSource& brick_source, const RenderOptions& render_options,
       const ViewerSettings& viewer_settings);

  ViewerResult run();

  void handle(const SDL_Event& event);
  void handle_key(const SDL_KeyboardEvent& key);
  void mark_interaction();
  void take_camera();  // the user moves the camera: the scene's orbit stops
  bool interacting(Clock::time_point now) const;
  // Busy (the user interacting, the turntable turning): fetch no finer than the start.
  // Idle, converged at the cap: lift it one level if the cache holds what that needs.
  void update_cap(bool busy);

  // The objects a texture key applies to: the one under the cursor, else all.
  std::vector<std::size_t> texture_targets(bool all);
  // Gives each target the texture chosen(current choice), -1 being the scene's own, and
  // re-prepares the scene; on failure (a source refusing the texture) keeps the old ones.
  template <typename Choose>
  void switch_textures(bool all, Choose chosen);
  void move_clip_planes(double distance);
  void rebuild_renderer();
  void prepare();  // prepare_scene() and a cap for its textures, at the current cap

  double level_bias() const;
  void draw_frame(ViewerResult& result, Clock::time_point run_start);
  void present(const Image& image);
  void show_status(bool idle);
  void write_screenshot(const Image& image) const;

  SdlVideo video;  // first: outlives the window, renderer and texture below
  std::unique_ptr<SDL_Window, SdlDestroy> window;
  std::unique_ptr<SDL_Renderer, SdlDestroy> sdl_renderer;
  std::unique_ptr<SDL_Texture, SdlDestroy> texture;

  Scene scene;
  std::vector<TextureSpec> scene_textures;  // each object's texture in the scene as given
  std::vector<int> texture_choice;          // per object: lecture texture index, -1: the scene's
  TextureResolution resolution;
  BrickCache& cache;
  net::BrickSource& source;
  RenderOptions options;  // as asked for; the adaptive bias is added to options.level_bias
  ViewerSettings settings;
  PreparedScene prepared;
  std::unique_ptr<FrameRenderer> renderer;
  OrbitController orbit;
  Turntable turntable;
  LevelCap cap;
  std::vector<net::BrickWant> last_misses;  // the last frame's, before the cap
  bool complete_at_cap = false;             // the last frame drew all it draws at the cap
  LevelBiasController bias_controller;
  bool adaptive_bias;
  // What I turns anisotropic taps back on to: the --anisotropy given, or the default where
  // the view started without them.
  int taps_when_on = 0;
  ObjectPicker picker;

  bool quit = false;
  bool dirty = true;  // something changed since the last frame: draw again
  bool was_interacting = false;
  bool dragging = false;
  int cursor_x = -1;  // frame pixels (the renderer scales events to the frame's size)
  int cursor_y = -1;
  Clock::time_point last_interaction{};
  uint64_t received_at_last_frame = 0;

  // Window title statistics since the last title.
  Clock::time_point title_shown_at{};
  int frames_since_title = 0;
  double last_frame_ms = 0.0;
  BrickCacheStats cache_at_title;  // the hit rate shown is the interval's, not the session's
  double shown_hit_rate = 0.0;
};

ViewerWindow::Impl::Impl(Scene scene_to_show, const TextureResolution& texture_resolution,
                         BrickCache& brick_cache, net::BrickSource& brick_source,
                         const RenderOptions& render_options, const ViewerSettings& viewer_settings)
    : scene(std::move(scene_to_show)),
      resolution(texture_resolution),
      cache(brick_cache),
      source(brick_source),
      options(render_options),
      settings(viewer_settings),
      orbit(scene.camera),
      turntable(scene.orbit),
      bias_controller(viewer_settings.level_bias),
      adaptive_bias(viewer_settings.adaptive_level_bias) {
  if (settings.width <= 0 || settings.height <= 0) {
    throw std::invalid_argument("viewer frame size must be positive");
  }
  window.reset(SDL_CreateWindow("soltex-view", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                settings.width, settings.height, SDL_WINDOW_RESIZABLE));
  if (!window) throw sdl_error("cannot open a window");
  // No vsync: the frame time the adaptive bias holds must be the renderer's, not the display's.
  sdl_renderer.reset(SDL_CreateRenderer(window.get(), -1, 0));
  if (!sdl_renderer)
    sdl_renderer.reset(SDL_CreateRenderer(window.get(), -1, SDL_RENDERER_SOFTWARE));
  if (!sdl_renderer) throw sdl_error("cannot create an SDL renderer");
  SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "linear");
  // A resized window shows the whole frame, letterboxed, and mouse events arrive in frame
  // pixels, which is what picking needs.
  SDL_RenderSetLogicalSize(sdl_renderer.get(), settings.width, settings.height);
  texture.reset(SDL_CreateTexture(sdl_renderer.get(), SDL_PIXELFORMAT_RGB24,
                                  SDL_TEXTUREACCESS_STREAMING, settings.width, settings.height));
  if (!texture) throw sdl_error("cannot create the frame texture");

  for (const SceneObject& object : scene.objects) scene_textures.push_back(object.material.texture);
  texture_choice.assign(scene.objects.size(), -1);
  cap.set_cap_log2(settings.start_level_log2 > 0 ? settings.start_level_log2 : INT_MAX);
  prepare();
  rebuild_renderer();
}

void ViewerWindow::Impl::prepare() {
  prepared = prepare_scene(scene, resolution, source);
  warn_of_refused_textures(prepared);
  LevelCap fresh(prepared);
  fresh.set_cap_log2(cap.cap_log2());
  cap = std::move(fresh);
  complete_at_cap = false;
}

void ViewerWindow::Impl::update_cap(bool busy) {
  const int start = settings.start_level_log2 > 0 ? settings.start_level_log2 : INT_MAX;
  if (busy) {
    // Bricks finer than the start would take the link from what the moving view needs;
    // those already resident still draw (the renderer uses the finest level it holds).
    if (cap.cap_log2() > start) cap.set_cap_log2(start);
    return;
  }
  // The last frame is final at this cap: all it wanted was resident, nothing is on its way,
  // and nothing arrived since (which would call for another frame first).
  if (!complete_at_cap || !cap.active() || !source.idle() ||
      source.stats().received != received_at_last_frame) {
    return;
  }
  const int next = next_cap(cap, last_misses, cache, 1);
  if (next == cap.cap_log2()) return;
  cap.set_cap_log2(next);
  complete_at_cap = false;
  dirty = true;
  spdlog::debug("still: refining to level 2^{}", next);
}

void ViewerWindow::Impl::rebuild_renderer() {
  renderer = std::make_unique<FrameRenderer>(cache, options);
  dirty = true;
}

double ViewerWindow::Impl::level_bias() const {
  return options.level_bias + (adaptive_bias ? bias_controller.bias() : 0.0);
}

void ViewerWindow::Impl::mark_interaction() {
  last_interaction = Clock::now();
  dirty = true;
}

void ViewerWindow::Impl::take_camera() {
  turntable.stop();
  mark_interaction();
}

bool ViewerWindow::Impl::interacting(Clock::time_point now) const {
  return now - last_interaction < kInteractionHold;
}

void ViewerWindow::Impl::handle(const SDL_Event& event) {
  switch (event.type) {
    case SDL_QUIT:
      quit = true;
      break;
    case SDL_WINDOWEVENT:
      // Exposed or resized: the window's contents must be drawn again.
      dirty = true;
      break;
    case SDL_MOUSEBUTTONDOWN:
      if (event.button.button == SDL_BUTTON_LEFT) dragging = true;
      break;
    case SDL_MOUSEBUTTONUP:
      if (event.button.button == SDL_BUTTON_LEFT) dragging = false;
      break;
    case SDL_MOUSEMOTION:
      cursor_x = event.motion.x;
      cursor_y = event.motion.y;
      if (dragging && (event.motion.state & SDL_BUTTON_LMASK) != 0) {
        // Dragging right turns the scene to the right: the camera goes the other way.
        orbit.rotate(-kOrbitDegreesPerPixel * event.motion.xrel,
                     kOrbitDegreesPerPixel * event.motion.yrel);
        take_camera();
      }
      break;
    case SDL_MOUSEWHEEL: {
#if SDL_VERSION_ATLEAST(2, 0, 18)
      double steps = event.wheel.preciseY;
#else
      double steps = event.wheel.y;
#endif
      if (event.wheel.direction == SDL_MOUSEWHEEL_FLIPPED) steps = -steps;
      if (steps != 0.0) {
        orbit.zoom(steps);
        take_camera();
      }
      break;
    }
    case SDL_KEYDOWN:
      handle_key(event.key);
      break;
    default:
      break;
  }
}

void ViewerWindow::Impl::handle_key(const SDL_KeyboardEvent& key) {
  const SDL_Keycode code = key.keysym.sym;
  const bool shift = (key.keysym.mod & KMOD_SHIFT) != 0;
  const bool repeat = key.repeat != 0;
  const int texture_count = static_cast<int>(lecture_textures().size());
  const double clip_step = kClipStepPerDistance * orbit.distance();

  switch (code) {
    case SDLK_UP:
      move_clip_planes(clip_step);
      return;
    case SDLK_DOWN:
      move_clip_planes(-clip_step);
      return;
    case SDLK_PAGEUP:
      move_clip_planes(kFastClipStepFactor * clip_step);
      return;
    case SDLK_PAGEDOWN:
      move_clip_planes(-kFastClipStepFactor * clip_step);
      return;
    default:
      break;
  }
  if (repeat) return;  // the other keys toggle or switch: one press, one change

  if (const std::optional<int> index = texture_key(code)) {
    if (*index < texture_count) switch_textures(shift, [&](int) { return *index; });
    return;
  }
  switch (code) {
    case SDLK_ESCAPE:
    case SDLK_q:
      quit = true;
      break;
    case SDLK_TAB:
      // From the scene's own texture (-1), Tab goes to the first and Shift+Tab to the last.
      switch_textures(false, [&](int current) {
        if (shift) return current <= 0 ? texture_count - 1 : current - 1;
        return (current + 1) % texture_count;
      });
      break;
    case SDLK_0:
    case SDLK_KP_0:
      switch_textures(shift, [](int) { return -1; });
      break;
    case SDLK_l:
      options.false_colour_levels = !options.false_colour_levels;
      rebuild_renderer();
      break;
    case SDLK_f:
      options.filter = next_filter(options.filter);
      rebuild_renderer();
      spdlog::info("filter: {}", sample_filter_name(options.filter));
      break;
    case SDLK_i:
      if (taps_when_on == 0) {
        taps_when_on = options.anisotropy > 1 ? options.anisotropy : RenderOptions{}.anisotropy;
      }
      options.anisotropy = options.anisotropy > 1 ? 1 : taps_when_on;
      rebuild_renderer();
      spdlog::info("anisotropic taps: {}", options.anisotropy > 1
                                               ? "up to " + std::to_string(options.anisotropy)
                                               : std::string("off (one lookup per pixel)"));
      break;
    case SDLK_a:
      adaptive_bias = !adaptive_bias;
      bias_controller.reset();
      dirty = true;
      spdlog::info("adaptive level bias {}", adaptive_bias ? "on" : "off");
      break;
    case SDLK_r:
      orbit.reset();
      turntable.restart();
      mark_interaction();
      break;
    default:
      break;
  }
}

std::vector<std::size_t> ViewerWindow::Impl::texture_targets(bool all) {
  if (!all) {
    if (const std::optional<std::size_t> picked = picker.pick(
            prepared, orbit.camera(), settings.width, settings.height, cursor_x, cursor_y)) {
      return {*picked};
    }
  }
  std::vector<std::size_t> targets(scene.objects.size());
  for (std::size_t i = 0; i < targets.size(); ++i) targets[i] = i;
  return targets;
}

template <typename Choose>
void ViewerWindow::Impl::switch_textures(bool all, Choose chosen) {
  const std::vector<std::size_t> targets = texture_targets(all);
  if (targets.empty()) return;
  const std::vector<int> previous_choice = texture_choice;
  const auto set_textures = [&] {
    for (std::size_t i : targets) {
      const int choice = texture_choice[i];
      scene.objects[i].material.texture =
          choice < 0 ? scene_textures[i]
                     : lecture_textures()[static_cast<std::size_t>(choice)].spec;
    }
  };
  for (std::size_t i : targets) texture_choice[i] = chosen(texture_choice[i]);
  set_textures();
  try {
    prepare();
  } catch (const std::exception& e) {
    // `prepared` is untouched and still matches the old textures.
    spdlog::error("cannot switch textures: {}", e.what());
    texture_choice = previous_choice;
    set_textures();
    return;
  }
  for (std::size_t i : targets) {
    const int choice = texture_choice[i];
    spdlog::info("{}: {}", scene.objects[i].name,
                 choice < 0 ? std::string("the scene's texture")
                            : lecture_textures()[static_cast<std::size_t>(choice)].name);
  }
  dirty = true;
}

void ViewerWindow::Impl::move_clip_planes(double distance) {
  if (prepared.clip_planes.empty()) return;
  // A ClipPlane keeps normal.p <= offset; its raster form (-normal, offset) keeps
  // -normal.p + offset >= 0, so both offsets move together. The scene keeps the new place
  // for the next prepare_scene.
  for (SceneObject& object : scene.objects) {
    for (ClipPlane& plane : object.clip_planes) plane.offset += distance;
  }
  for (glm::dvec4& plane : prepared.clip_planes) plane.w += distance;
  dirty = true;
}

void ViewerWindow::Impl::present(const Image& image) {
  SDL_UpdateTexture(texture.get(), nullptr, image.rgb.data(), image.width * 3);
  SDL_SetRenderDrawColor(sdl_renderer.get(), 0, 0, 0, 255);
  SDL_RenderClear(sdl_renderer.get());
  SDL_RenderCopy(sdl_renderer.get(), texture.get(), nullptr, nullptr);
  SDL_RenderPresent(sdl_renderer.get());
}

void ViewerWindow::Impl::draw_frame(ViewerResult& result, Clock::time_point run_start) {
  const auto start = Clock::now();
  const bool interacting_now = interacting(start);
  if (const std::optional<double> turn = turntable.next_angle(start)) {
    orbit.set_turn(*turn);
    last_interaction = start;  // a moving view: hold the frame time, fetch coarse
  }
  // Bricks arriving from here on are not in this frame, and call for the next one.
  received_at_last_frame = source.stats().received;
  adopt_refused_textures(prepared, source);
  renderer->set_level_bias(level_bias());
  Frame frame = renderer->render(prepared, orbit.camera(), settings.width, settings.height);
  FrameNeeds needs = needs_of(frame, cap.active() ? &cap : nullptr, &cache,
                              source.stats().received != received_at_last_frame);
  complete_at_cap = needs.complete;
  source.want(std::move(needs.wants));
  last_misses = std::move(frame.misses);
  present(frame.image);
  const auto end = Clock::now();

  last_frame_ms = ms_between(start, end);
  ++frames_since_title;
  if (result.frames++ == 0) result.first_frame_ms = ms_between(run_start, end);
  result.last_image = std::move(frame.image);
  dirty = false;
  if (adaptive_bias) {
    const double bias_before = bias_controller.bias();
    bias_controller.record_frame(last_frame_ms, interacting_now);
    if (bias_controller.bias() != bias_before) dirty = true;
  }
}

void ViewerWindow::Impl::show_status(bool idle) {
  const auto now = Clock::now();
  if (now - title_shown_at < kTitleInterval) return;
  const double seconds = std::chrono::duration<double>(now - title_shown_at).count();
  const net::SourceStats fetched = source.stats();
  ViewerStatus status;
  status.frames_per_second = seconds > 0.0 && seconds < 60.0 ? frames_since_title / seconds : 0.0;
  status.frame_ms = last_frame_ms;
  const BrickCacheStats cached = cache.stats();
  BrickCacheStats interval;
  interval.lookups = cached.lookups - cache_at_title.lookups;
  interval.hits = cached.hits - cache_at_title.hits;
  // No lookups (no frames) since the last title: the last rate still stands.
  if (interval.lookups > 0) shown_hit_rate = interval.hit_rate();
  cache_at_title = cached;
  status.cache_hit_rate = shown_hit_rate;
  status.pending_bricks = fetched.waiting + fetched.in_flight;
  status.bytes_received = fetched.bytes;
  status.level_bias = level_bias();
  status.adaptive_bias = adaptive_bias;
  status.filter = sample_filter_name(options.filter);
  status.false_colour_levels = options.false_colour_levels;
  status.idle = idle && frames_since_title == 0;
  SDL_SetWindowTitle(window.get(), window_title(status).c_str());
  title_shown_at = now;
  frames_since_title = 0;
}

void ViewerWindow::Impl::write_screenshot(const Image& image) const {
  if (settings.screenshot.empty()) return;
  if (image.width == 0) throw std::runtime_error("no frame was drawn, so there is no screenshot");
  if (!settings.screenshot.parent_path().empty()) {
    std::filesystem::create_directories(settings.screenshot.parent_path());
  }
  write_png(settings.screenshot, image);
}

ViewerResult ViewerWindow::Impl::run() {
  ViewerResult result;
  const auto run_start = Clock::now();
  // Counting frames (screenshots, tests) draws every iteration, so N frames take N draws.
  const bool draw_always = settings.max_frames > 0;
  while (!quit) {
    SDL_Event event;
    while (SDL_PollEvent(&event)) handle(event);
    if (quit) break;

    const auto now = Clock::now();
    const bool interacting_now = interacting(now);
    // The interaction just ended: one more frame, which drops the adaptive bias.
    if (was_interacting && !interacting_now) dirty = true;
    was_interacting = interacting_now;
    if (turntable.playing()) dirty = true;
    update_cap(interacting_now || turntable.playing());

    const bool bricks_arrived = source.stats().received != received_at_last_frame;
    if (dirty || bricks_arrived || draw_always) {
      draw_frame(result, run_start);
      show_status(false);
      if (draw_always && result.frames >= settings.max_frames) break;
    } else {
      show_status(true);
      if (SDL_WaitEventTimeout(&event, kIdleWaitMs) != 0) handle(event);
    }
  }
  write_screenshot(result.last_image);
  return result;
}

ViewerWindow::ViewerWindow(Scene scene, const TextureResolution& resolution, BrickCache& cache,
                           net::BrickSource& source, const RenderOptions& options,
                           const ViewerSettings& settings)
    : impl_(
          std::make_unique<Impl>(std::move(scene), resolution, cache, source, options, settings)) {}

ViewerWindow::~ViewerWindow() = default;

ViewerResult ViewerWindow::run() {
  return impl_->run();
}

}  // namespace soltex::view
