#include "accuracy_command.h"

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "accuracy_plot.h"
#include "accuracy_report.h"
#include "accuracy_run.h"
#include "accuracy_sweep.h"
#include "soltex/cli/tool_cli.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/scene_loader.h"

namespace soltex::bench {
namespace {

int or_default(int given, int normal, int quick, bool is_quick) {
  return given > 0 ? given : is_quick ? quick : normal;
}

// The command line that repeats this run, for the report.
std::string command_line(const AccuracyCommandOptions& o, const SweepOptions& sweep) {
  std::string command = "soltex-bench accuracy";
  if (!o.scene.empty()) command += " --scene " + o.scene.string();
  if (o.quick) command += " --quick";
  command += " --width " + std::to_string(sweep.size.width) + " --height " +
             std::to_string(sweep.size.height);
  if (o.threads > 0) command += " --threads " + std::to_string(o.threads);
  command += std::string(" --front-clock ") + frame_clock_name(sweep.front_clock);
  command += " --rounds " + std::to_string(sweep.rounds) + " --frames-per-round " +
             std::to_string(sweep.frames_per_round);
  return command;
}

}  // namespace

CLI::App* add_accuracy_command(CLI::App& app, AccuracyCommandOptions& options) {
  CLI::App* command = app.add_subcommand(
      "accuracy",
      "sweep the accuracy knobs (finest level, brick size, filter, MIP construction, turbulence "
      "octaves, codec) one at a time around the default, plus finest level x filter; measure "
      "error against a supersampled reference, frame time, brick cost, bytes and memory; write "
      "a Markdown table, a CSV and an SVG plot with the Pareto front");
  command->add_option("--scene", options.scene, "scene file (JSON); default: the built-in scene")
      ->check(CLI::ExistingFile);
  command->add_option("--width", options.width, "frame width (default 640; 160 with --quick)")
      ->check(cli::IntegerIn(8, 16384));
  command->add_option("--height", options.height, "frame height (default 360; 90 with --quick)")
      ->check(cli::IntegerIn(8, 16384));
  command->add_flag("--quick", options.quick,
                    "a handful of settings on a tiny frame, fewer measuring rounds (a smoke test)");
  command
      ->add_option("--out-dir", options.out_dir,
                   "folder for accuracy.md, accuracy.csv and accuracy.svg")
      ->capture_default_str();
  command->add_option("--md", options.markdown, "Markdown table (default: OUT_DIR/accuracy.md)");
  command->add_option("--csv", options.csv, "CSV (default: OUT_DIR/accuracy.csv)");
  command
      ->add_option("--svg", options.svg,
                   "plot, drawn by plot_accuracy.py with matplotlib; .svg or .png "
                   "(default: OUT_DIR/accuracy.svg)")
      ->check(CLI::Validator(
          [](std::string& path) -> std::string {
            // Known before the sweep, not after it: matplotlib writes these two here.
            const std::string extension = std::filesystem::path(path).extension().string();
            return extension == ".svg" || extension == ".png" ? "" : "must end in .svg or .png";
          },
          "PATH"));
  command->add_option("--threads", options.threads, "render threads (0: one per core)")
      ->check(cli::IntegerIn(0, 256));
  command
      ->add_option("--rounds", options.rounds,
                   "measuring rounds over all settings (default 30; 2 with --quick)")
      ->check(cli::IntegerIn(1, 1000));
  command
      ->add_option("--frames-per-round", options.frames_per_round,
                   "timed frames per setting and round (default 2; 1 with --quick)")
      ->check(cli::IntegerIn(1, 1000));
  command
      ->add_option("--max-converge-s,--max-converge-seconds", options.max_converge_seconds,
                   "give up on a setting whose frame has not converged after this long")
      ->check(soltex::cli::NumberIn(1.0, 3600.0))
      ->capture_default_str();
  command
      ->add_option("--front-clock", options.front_clock,
                   "the frame time the Pareto front and the plot go by: cpu (CPU time of "
                   "all render threads, steady on a shared machine) or wall")
      ->check(CLI::IsMember({"cpu", "wall"}))
      ->capture_default_str();
  command->add_option("--images", options.images,
                      "also write the reference and every setting's converged frame as PNG here");
  return command;
}

int run_accuracy_command(const AccuracyCommandOptions& options) {
  SweepOptions sweep;
  sweep.size.width = or_default(options.width, 640, 160, options.quick);
  sweep.size.height = or_default(options.height, 360, 90, options.quick);
  sweep.threads = options.threads;
  sweep.rounds = or_default(options.rounds, 30, 2, options.quick);
  sweep.frames_per_round = or_default(options.frames_per_round, 2, 1, options.quick);
  sweep.images = options.images;
  sweep.front_clock = options.front_clock == "wall" ? FrameClock::wall : FrameClock::cpu;
  sweep.max_converge =
      std::chrono::milliseconds(static_cast<long>(options.max_converge_seconds * 1000.0));
  const std::filesystem::path markdown =
      options.markdown.empty() ? options.out_dir / "accuracy.md" : options.markdown;
  const std::filesystem::path csv =
      options.csv.empty() ? options.out_dir / "accuracy.csv" : options.csv;
  const std::filesystem::path svg =
      options.svg.empty() ? options.out_dir / "accuracy.svg" : options.svg;

  Scene scene;
  try {
    scene = options.scene.empty() ? default_scene() : load_scene(options.scene);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soltex-bench: %s\n", e.what());
    return 2;
  }
  try {
    const std::vector<AccuracySetting> settings = accuracy_sweep(scene, options.quick);
    const std::string scene_name =
        options.scene.empty() ? "default scene" : options.scene.filename().string();
    const AccuracyRun run = run_accuracy_sweep(scene, scene_name, settings, sweep);
    write_markdown(run, command_line(options, sweep), markdown, svg);
    write_csv(run, csv);
    // Without a plot the table and the CSV still stand; write_plot says what is missing.
    const bool plotted = write_plot(run, csv, svg);
    std::printf("%zu settings measured; wrote %s, %s%s%s\n", run.results.size(), markdown.c_str(),
                csv.c_str(), plotted ? ", " : "", plotted ? svg.c_str() : "");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\nsoltex-bench: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace soltex::bench
