// soltex-bench: measurements of the client as a whole. `accuracy` sweeps the knobs that trade
// image accuracy for time, bytes and memory.
#include <CLI/CLI.hpp>

#include "accuracy_command.h"

int main(int argc, char** argv) {
  CLI::App app{"soltex-bench: what the client's settings cost, measured"};
  app.require_subcommand(1);
  soltex::bench::AccuracyCommandOptions accuracy;
  CLI::App* accuracy_command = soltex::bench::add_accuracy_command(app, accuracy);
  CLI11_PARSE(app, argc, argv);
  if (accuracy_command->parsed()) return soltex::bench::run_accuracy_command(accuracy);
  return 2;
}
