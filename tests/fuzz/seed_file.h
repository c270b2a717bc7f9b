#pragma once
// What every seed writer does: check its arguments, create its directories, write each seed's
// bytes to one file, and report a failure.

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace soltex::fuzz {

// Throws std::runtime_error naming the file when it cannot be written.
inline void write_seed_file(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// A seed writer's main(): expects one directory argument per name in `dir_names` (the usage
// line shows them), creates them, and hands them to `write`. Returns the process status: 2 on
// bad arguments, 1 when `write` throws (the message names the writer), else 0.
inline int seed_writer_main(
    int argc, char** argv, std::vector<const char*> dir_names,
    const std::function<void(const std::vector<std::filesystem::path>&)>& write) {
  if (argc != static_cast<int>(dir_names.size()) + 1) {
    std::fprintf(stderr, "usage: %s", argv[0]);
    for (const char* name : dir_names) std::fprintf(stderr, " <%s>", name);
    std::fprintf(stderr, "\n");
    return 2;
  }
  const std::string program = std::filesystem::path(argv[0]).filename().string();
  try {
    std::vector<std::filesystem::path> dirs(argv + 1, argv + argc);
    for (const std::filesystem::path& dir : dirs) std::filesystem::create_directories(dir);
    write(dirs);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", program.c_str(), e.what());
    return 1;
  }
  return 0;
}

}  // namespace soltex::fuzz
