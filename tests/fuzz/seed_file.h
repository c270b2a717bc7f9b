#pragma once
// What every seed writer does with a seed: write its bytes to one file of the corpus.

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string_view>

namespace soltex::fuzz {

// Throws std::runtime_error naming the file when it cannot be written.
inline void write_seed_file(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace soltex::fuzz
