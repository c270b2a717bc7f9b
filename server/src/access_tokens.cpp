#include "access_tokens.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "soltex/common/text_file.h"

namespace soltex::server {
namespace {

constexpr std::size_t kMaxNameLength = 64;
constexpr std::size_t kMaxSecretLength = 4096;

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

std::vector<std::string_view> fields_of(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

// Names appear in logs, metrics and messages: keep them short and printable.
bool valid_name(std::string_view name) {
  return !name.empty() && name.size() <= kMaxNameLength &&
         std::all_of(name.begin(), name.end(), [](char c) {
           return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                  c == '.' || c == '_' || c == '-' || c == '@';
         });
}

}  // namespace

std::vector<AccessToken> parse_access_tokens(std::string_view text, const std::string& origin) {
  std::vector<AccessToken> tokens;
  std::vector<int> lines;  // each token's line
  int number = 0;
  while (!text.empty()) {
    const auto end = text.find('\n');
    const std::string_view line = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++number;
    const std::vector<std::string_view> fields = fields_of(line);
    if (fields.empty() || fields[0].starts_with('#')) continue;
    const std::string where = origin + " line " + std::to_string(number) + ": ";
    if (fields.size() > 2) {
      throw std::runtime_error(where + "expected 'NAME TOKEN' or 'TOKEN', found " +
                               std::to_string(fields.size()) + " fields");
    }
    AccessToken token;
    if (fields.size() == 2) token.name = std::string(fields[0]);
    token.secret = std::string(fields.back());
    if (fields.size() == 2 && !valid_name(token.name)) {
      throw std::runtime_error(where + "token name '" + token.name +
                               "' must be 1 to 64 characters of A-Z a-z 0-9 . _ - @");
    }
    if (token.secret.size() > kMaxSecretLength) {
      throw std::runtime_error(where + "token of " + std::to_string(token.secret.size()) +
                               " characters; at most " + std::to_string(kMaxSecretLength));
    }
    tokens.push_back(std::move(token));
    lines.push_back(number);
  }
  // Secrets are looked up only after the file is read: `tokens` no longer moves.
  std::unordered_map<std::string_view, int> first_line;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const auto [seen, added] = first_line.emplace(tokens[i].secret, lines[i]);
    if (!added) {
      throw std::runtime_error(
          origin + " line " + std::to_string(lines[i]) + ": the same token as line " +
          std::to_string(seen->second) +
          (tokens[i].name.empty() ? "" : " (again as '" + tokens[i].name + "')"));
    }
  }
  if (tokens.empty()) throw std::runtime_error(origin + ": holds no token");
  return tokens;
}

std::vector<AccessToken> read_access_tokens(const std::string& path) {
  return parse_access_tokens(read_text_file(path, "tokens"), "tokens file '" + path + "'");
}

}  // namespace soltex::server
