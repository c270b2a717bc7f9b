// Writes the starting corpus of materialx_reader_fuzz: the example documents of
// deploy/scenes/graphs and a small hand-written one per supported node.
//
//   materialx_seed_writer <corpus-dir> <examples-dir>

#include <filesystem>
#include <string>

#include "seed_file.h"

namespace {

const char* const kCategories[] = {
    "add",   "subtract",   "multiply", "divide",  "modulo",    "power",       "min",
    "max",   "absval",     "floor",    "ceil",    "sin",       "cos",         "sqrt",
    "clamp", "smoothstep", "remap",    "noise3d", "fractal3d", "cellnoise3d", "worleynoise3d"};

// position -> <category> (float) -> convert to color3 -> out
std::string one_node_document(const std::string& category) {
  const bool positional = category.find("noise") != std::string::npos || category == "fractal3d";
  const std::string input = positional
                                ? "<input name=\"position\" type=\"vector3\" nodename=\"p\" />"
                                : "<input name=\"in1\" type=\"float\" nodename=\"x\" />"
                                  "<input name=\"in\" type=\"float\" nodename=\"x\" />";
  return "<?xml version=\"1.0\"?>\n<materialx version=\"1.38\">\n<nodegraph name=\"g\">\n"
         "<position name=\"p\" type=\"vector3\" />\n"
         "<extract name=\"x\" type=\"float\"><input name=\"in\" type=\"vector3\" nodename=\"p\" />"
         "</extract>\n<" +
         category + " name=\"n\" type=\"float\">" + input + "</" + category +
         ">\n<convert name=\"c\" type=\"color3\"><input name=\"in\" type=\"float\" nodename=\"n\" "
         "/>"
         "</convert>\n<output name=\"out\" type=\"color3\" nodename=\"c\" />\n</nodegraph>\n"
         "</materialx>\n";
}

}  // namespace

int main(int argc, char** argv) {
  return soltex::fuzz::seed_writer_main(
      argc, argv, {"corpus-dir", "examples-dir"},
      [](const std::vector<std::filesystem::path>& dirs) {
        for (const auto& entry : std::filesystem::directory_iterator(dirs[1])) {
          if (entry.path().extension() == ".mtlx") {
            std::filesystem::copy_file(entry.path(), dirs[0] / entry.path().filename(),
                                       std::filesystem::copy_options::overwrite_existing);
          }
        }
        for (const char* category : kCategories) {
          soltex::fuzz::write_seed_file(dirs[0] / (std::string(category) + ".mtlx"),
                                        one_node_document(category));
        }
      });
}
