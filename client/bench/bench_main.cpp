// soltex-bench: measurements of the client as a whole. `accuracy` sweeps the knobs that trade
// image accuracy for time, bytes and memory.
#include <CLI/CLI.hpp>

#include "accuracy_command.h"
#include "soltex/cli/tool_cli.h"

int main(int argc, char** argv) {
  namespace cli = soltex::cli;
  CLI::App app{"soltex-bench: what the client's settings cost, measured"};
  app.require_subcommand(1);
  std::string log_level = "info";
  cli::add_common_options(app, "soltex-bench", log_level);
  soltex::bench::AccuracyCommandOptions accuracy;
  CLI::App* accuracy_command = soltex::bench::add_accuracy_command(app, accuracy);
  // --log-level and the other common options after the subcommand's name too, as every
  // tool's options may come in any order.
  accuracy_command->fallthrough();
  if (const auto exit_code = cli::parse(app, "soltex-bench", argc, argv)) return *exit_code;
  cli::start_logging("soltex-bench", log_level);
  if (accuracy_command->parsed()) return soltex::bench::run_accuracy_command(accuracy);
  return cli::kExitUsage;
}
