#include "soltex/common/text_file.h"

#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace soltex {

std::string read_text_file(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read the " + what + " file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string read_trimmed_text_file(const std::string& path, const std::string& what) {
  std::string text = read_text_file(path, what);
  const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!text.empty() && space(text.back())) text.pop_back();
  std::size_t first = 0;
  while (first < text.size() && space(text[first])) ++first;
  text.erase(0, first);
  if (text.empty()) throw std::runtime_error("the " + what + " file '" + path + "' is empty");
  return text;
}

}  // namespace soltex
