#include "accuracy_report.h"

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "number_format.h"

namespace soltex::bench {
namespace {

std::ofstream open_for_writing(const std::filesystem::path& path) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  return out;
}

void close_checked(std::ofstream& out, const std::filesystem::path& path) {
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string max_abs_text(const ImageError& error) {
  return std::to_string(error.max_abs[0]) + "/" + std::to_string(error.max_abs[1]) + "/" +
         std::to_string(error.max_abs[2]);
}

double megabytes(double bytes) {
  return bytes / 1e6;
}
double mebibytes(double bytes) {
  return bytes / (1024.0 * 1024.0);
}

// The results on the front, one per frame (codec rows share their frame's point), fastest
// first.
std::vector<const SettingResult*> front_fastest_first(const AccuracyRun& run) {
  std::vector<const SettingResult*> front;
  for (std::size_t i = 0; i < run.results.size(); ++i) {
    const SettingResult& r = run.results[i];
    if (r.on_front && r.frame_group == static_cast<int>(i)) front.push_back(&r);
  }
  const FrameClock clock = run.options.front_clock;
  std::sort(front.begin(), front.end(), [clock](const SettingResult* a, const SettingResult* b) {
    return front_time(*a, clock).median_ms < front_time(*b, clock).median_ms;
  });
  return front;
}

// Median and quartiles; CPU times get a second decimal, their quartiles are that close.
std::string frame_time_text(const FrameTime& t, int decimals = 1) {
  return fixed(t.median_ms, decimals) + " (" + fixed(t.q1_ms, decimals) + "–" +
         fixed(t.q3_ms, decimals) + ")";
}

double evaluated_percent(const SettingResult& r) {
  if (r.covered_pixels == 0) return 0.0;
  return 100.0 * static_cast<double>(r.evaluated_pixels) / static_cast<double>(r.covered_pixels);
}

// What `auto` chose per texture, with the frames of the three access settings beside it.
void write_automatic_access(std::ofstream& out, const AccuracyRun& run) {
  out << "\n## Cache or evaluate\n\n"
      << "`auto` reads each texture by a fixed rule per pattern kind, from the per-pixel costs "
      << "measured by `build/tests/bench/access_bench` (docs/TEXTURES.md, \"Cache or "
      << "evaluate\"); no timing taken at run time decides it, so the image does not depend on "
      << "the machine. In this scene:\n\n"
      << "| object | pattern | auto reads it by |\n|---|---|---|\n";
  for (const TextureChoice& c : run.automatic_access) {
    out << "| " << c.object << " | " << c.pattern << " | "
        << (c.evaluated ? "evaluation per pixel (no bricks)" : "cached lookup") << " |\n";
  }
  out << "\n| access | PSNR dB | CPU ms/frame | ms/frame | eval px % | bricks | MB fetched | "
         "cache MiB |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const SettingResult& r : run.results) {
    const AccuracySetting& s = r.setting;
    AccuracySetting as_default;
    as_default.access = s.access;
    if (!(s == as_default)) continue;  // the default with only its access changed
    out << "| " << texture_access_name(s.access) << " | " << fixed(r.error.psnr_db, 2) << " | "
        << frame_time_text(r.frame_cpu, 2) << " | " << frame_time_text(r.frame) << " | "
        << fixed(evaluated_percent(r), 1) << " | " << r.cost.bricks << " | "
        << fixed(megabytes(static_cast<double>(r.cost.encoded_bytes)), 2) << " | "
        << fixed(mebibytes(static_cast<double>(r.resident_bytes)), 1) << " |\n";
  }
}

}  // namespace

void write_markdown(const AccuracyRun& run, const std::string& command,
                    const std::filesystem::path& path, const std::filesystem::path& plot) {
  std::ofstream out = open_for_writing(path);
  const SweepOptions& o = run.options;
  const char* clock_column = o.front_clock == FrameClock::cpu ? "CPU ms/frame" : "ms/frame";
  const std::filesystem::path plot_link = std::filesystem::absolute(plot).lexically_relative(
      std::filesystem::absolute(path).parent_path());
  out << "# What accuracy costs\n\n"
      << "Measured by `" << command << "` (client/bench/). Each setting changes one knob of the "
      << "default (finest level 8, bricks of 16, trilinear filter, band-limited MIP levels, the "
      << "scene's own turbulence octaves, zstd level 1, encoded as soltexd encodes; soltexd's own "
      << "default level, -200, is faster for about 4 % more bytes), plus a grid of finest level "
      << "x filter.\n\n"
      << "- **Scene:** " << run.scene_name << ", " << o.size.width << "x" << o.size.height
      << ", render threads: "
      << (o.threads > 0 ? std::to_string(o.threads) : std::string("one per core")) << ".\n"
      << "- **Machine:** " << run.machine << ", shared with other work: 1-minute load average "
      << fixed(run.load_before, 2) << " when the sweep started, " << fixed(run.load_after, 2)
      << " when it ended. Times are medians.\n"
      << "- **Error** of each setting's converged frame against the reference, per-pixel "
      << "evaluation of the textures " << run.reference_supersample << "x"
      << run.reference_supersample << " supersampled (" << fixed(run.reference_ms, 0)
      << " ms): PSNR over R, G and B; mean SSIM of the luminance over 8x8 windows; the "
      << "largest difference of one channel in 8-bit steps (max Δ).\n"
      << "- **For scale:** per-pixel evaluation without cache or supersampling (what "
      << "`soltex-view --reference` draws) scores " << fixed(run.per_pixel_error.psnr_db, 2)
      << " dB, SSIM " << fixed(run.per_pixel_error.ssim, 4) << ", max Δ "
      << max_abs_text(run.per_pixel_error) << ", in " << frame_time_text(run.per_pixel_frame)
      << " ms a frame (CPU " << frame_time_text(run.per_pixel_frame_cpu, 2)
      << " ms). The reference also smooths silhouettes, which only the antialias rows do.\n"
      << "- **ms/frame:** median wall time of `FrameRenderer::render` with every brick resident, "
      << "over " << o.rounds << " rounds x " << o.frames_per_round
      << " frames, and in parentheses the quartiles (the middle half of the frames); each round "
      << "draws every setting once, in a shuffled order, so changes in the machine's load fall "
      << "on all settings alike. Differences smaller than the quartile ranges are noise. **CPU "
         "ms/frame:** the "
      << "process's CPU time over the same frames, every render thread summed: it counts only "
      << "the time the frame ran, so the machine's other load moves it much less.\n"
      << "- **server µs/brick:** median CPU time, over the bricks the frame fetched and "
      << o.rounds << " passes (one per round), of `evaluate_brick` + `quantize` + "
      << "`encode_brick` on one thread (what soltexd spends on a brick it does not have yet); "
      << "**encode** is the codec's part of it, **decode** a client's work per brick (checksum "
      << "included).\n"
      << "- **bricks, MB:** the distinct bricks the frame fetched until it converged, and their "
      << "encoded size with the setting's codec. **cache MiB:** `BrickCache` resident bytes "
      << "(decoded samples and bookkeeping).\n"
      << "- **access:** how each texture is read per pixel: `cache` looks every one up in its "
      << "bricks, `evaluate` evaluates every one over the pixel's footprint (and fetches no "
      << "brick for it), `auto` (the default) follows the rule per pattern kind in "
      << "docs/TEXTURES.md, \"Cache or evaluate\". **eval px %:** the share of covered pixels "
      << "whose texture was evaluated.\n"
      << "- **AA:** `--antialias`, sub-pixels per axis for silhouettes and clip edges: the "
      << "frame's raster and shading work grows with its square, the textures' bricks stay "
      << "the same. **aniso:** `--anisotropy`, taps at most along a grazing footprint's long "
      << "side (1: one lookup per pixel; docs/TEXTURES.md, \"Anisotropic taps\").\n"
      << "- **Codec rows** draw the default's frame (the cache holds decoded bricks): same "
      << "error, frame time and cache; only bytes and brick times differ.\n"
      << "- **front:** on the Pareto front of median " << clock_column
      << " against PSNR (no other setting at least as fast and as accurate, and better in "
      << "one).\n\n"
      << "![PSNR against frame time](" << plot_link.generic_string() << ")\n\n"
      << "| setting | level | B | filter | MIP | octaves | codec | PSNR dB | SSIM | max Δ R/G/B "
         "| ms/frame | CPU ms/frame | server µs/brick | encode µs | decode µs | bricks "
         "| MB fetched | cache MiB | access | eval px % | AA | aniso | front |\n"
      << "|---|---:|---:|---|---|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---"
         "|---:|---:|---:|---|\n";
  for (const SettingResult& r : run.results) {
    const AccuracySetting& s = r.setting;
    out << "| " << s.label() << " | " << s.finest_level << " | " << s.brick_size << " | "
        << sample_filter_name(s.filter) << " | " << mip_mode_name(s.mip) << " | "
        << octaves_name(s.octave_cap) << " | " << s.codec.name() << " | "
        << fixed(r.error.psnr_db, 2) << " | " << fixed(r.error.ssim, 4) << " | "
        << max_abs_text(r.error) << " | " << frame_time_text(r.frame) << " | "
        << frame_time_text(r.frame_cpu, 2) << " | " << fixed(r.cost.server_us, 0) << " | "
        << fixed(r.cost.encode_us, 1) << " | " << fixed(r.cost.decode_us, 1) << " | "
        << r.cost.bricks << " | " << fixed(megabytes(static_cast<double>(r.cost.encoded_bytes)), 2)
        << " | " << fixed(mebibytes(static_cast<double>(r.resident_bytes)), 1) << " | "
        << texture_access_name(s.access) << " | " << fixed(evaluated_percent(r), 1) << " | "
        << s.antialias << " | " << s.anisotropy << " | " << (r.on_front ? "yes" : "") << " |\n";
  }
  write_automatic_access(out, run);
  const std::vector<const SettingResult*> front = front_fastest_first(run);
  out << "\n## The front as a choice\n\n"
      << "For a frame-time budget, the most accurate setting measured that fits it (the "
      << "budget ranges come from this run's medians):\n\n"
      << "| budget, " << clock_column << " | setting | ms/frame | CPU ms/frame | PSNR dB | "
      << "SSIM |\n"
      << "|---|---|---:|---:|---:|---:|\n";
  for (std::size_t k = 0; k < front.size(); ++k) {
    const SettingResult& r = *front[k];
    const std::string from = fixed(front_time(r, o.front_clock).median_ms, 2);
    const std::string budget =
        k + 1 < front.size()
            ? from + " to " + fixed(front_time(*front[k + 1], o.front_clock).median_ms, 2)
            : from + " or more";
    out << "| " << budget << " | " << r.setting.label() << " | " << frame_time_text(r.frame)
        << " | " << frame_time_text(r.frame_cpu, 2) << " | " << fixed(r.error.psnr_db, 2) << " | "
        << fixed(r.error.ssim, 4) << " |\n";
  }
  close_checked(out, path);
}

void write_csv(const AccuracyRun& run, const std::filesystem::path& path) {
  std::ofstream out = open_for_writing(path);
  out << "setting,finest_level,brick_size,filter,mip,octaves,codec,psnr_db,ssim,max_abs_r,"
         "max_abs_g,max_abs_b,frame_ms,frame_ms_q1,frame_ms_q3,cpu_ms,cpu_ms_q1,cpu_ms_q3,"
         "server_us_per_brick,encode_us_per_brick,decode_us_per_brick,bricks,bytes_fetched,"
         "resident_bytes,access,evaluated_pixels,covered_pixels,antialias,anisotropy,"
         "pareto_front\n";
  for (const SettingResult& r : run.results) {
    const AccuracySetting& s = r.setting;
    out << s.label() << "," << s.finest_level << "," << s.brick_size << ","
        << sample_filter_name(s.filter) << "," << mip_mode_name(s.mip) << ","
        << octaves_name(s.octave_cap) << "," << s.codec.name() << "," << fixed(r.error.psnr_db, 3)
        << "," << fixed(r.error.ssim, 5) << "," << r.error.max_abs[0] << "," << r.error.max_abs[1]
        << "," << r.error.max_abs[2] << "," << fixed(r.frame.median_ms, 2) << ","
        << fixed(r.frame.q1_ms, 2) << "," << fixed(r.frame.q3_ms, 2) << ","
        << fixed(r.frame_cpu.median_ms, 2) << "," << fixed(r.frame_cpu.q1_ms, 2) << ","
        << fixed(r.frame_cpu.q3_ms, 2) << "," << fixed(r.cost.server_us, 1) << ","
        << fixed(r.cost.encode_us, 2) << "," << fixed(r.cost.decode_us, 2) << "," << r.cost.bricks
        << "," << r.cost.encoded_bytes << "," << r.resident_bytes << ","
        << texture_access_name(s.access) << "," << r.evaluated_pixels << "," << r.covered_pixels
        << "," << s.antialias << "," << s.anisotropy << "," << (r.on_front ? 1 : 0) << "\n";
  }
  close_checked(out, path);
}

}  // namespace soltex::bench
