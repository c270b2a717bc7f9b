#pragma once

#include <cstddef>
#include <glm/vec3.hpp>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "soltex/common/quoted_text.h"

// Typed, bounded reading of a JSON document that knows where it is: every failure throws
// SceneError naming the file, the field path ("objects[2].transform.scale") and the problem.
namespace soltex {

// Shortest round-trip text of a number, for messages.
std::string format_number(double value);

class JsonValue {
 public:
  JsonValue(const nlohmann::json& json, std::string path, const std::string& file)
      : json_(&json), path_(std::move(path)), file_(&file) {}

  const nlohmann::json& json() const { return *json_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return *file_; }

  [[noreturn]] void fail(const std::string& problem) const;
  // Fails with "expected <what>, found <type>" unless ok.
  void expect(bool ok, const char* what) const;

  // A finite number in [lo, hi].
  double number(double lo, double hi) const;
  // An integer in [lo, hi]; 3.0 counts as an integer, 3.5 does not.
  int integer(int lo, int hi) const;
  bool boolean() const;
  std::string string() const;
  // [x, y, z] or {"x": .., "y": .., "z": ..}, each component in [lo, hi].
  glm::dvec3 vec3(double lo, double hi) const;
  // [r, g, b] or {"r": .., "g": .., "b": ..}, each component in [0, 1].
  glm::vec3 colour() const;
  // The elements of an array of at most max_count elements.
  std::vector<JsonValue> elements(std::size_t max_count) const;

  // One of a fixed set of names.
  template <class Enum>
  Enum choice(std::initializer_list<std::pair<const char*, Enum>> names) const {
    const std::string text = string();
    std::string expected;
    for (const auto& [name, value] : names) {
      if (text == name) return value;
      expected += (expected.empty() ? "" : ", ") + std::string(name);
    }
    fail("unknown value " + quoted_text(text) + ": expected one of " + expected);
  }

  JsonValue child(const std::string& key) const;
  JsonValue element(std::size_t index) const;

 private:
  const nlohmann::json* json_;
  std::string path_;
  const std::string* file_;
};

// A JSON object read key by key. It remembers every key asked for, present or not, so
// reject_unknown_keys() can refuse the others: a misspelt optional field is an error, not a
// silently applied default.
class JsonObject {
 public:
  explicit JsonObject(const JsonValue& value);

  const JsonValue& value() const { return value_; }
  bool has(const char* key) const { return value_.json().contains(key); }

  std::optional<JsonValue> find(const char* key);
  JsonValue get(const char* key);  // required

  double number(const char* key, double fallback, double lo, double hi);
  int integer(const char* key, int fallback, int lo, int hi);
  bool boolean(const char* key, bool fallback);
  glm::dvec3 vec3(const char* key, const glm::dvec3& fallback, double lo, double hi);
  glm::vec3 colour(const char* key, const glm::vec3& fallback);

  // Exactly one of `choices` must be present; returns its index. `other_fields` are the
  // object's remaining fields: when no choice is present, a key that is neither is named as
  // the likely misspelt choice.
  std::size_t one_of(std::initializer_list<const char*> choices,
                     std::initializer_list<const char*> other_fields = {});

  void reject_unknown_keys() const;

 private:
  JsonValue value_;
  std::vector<std::string> known_;
};

}  // namespace soltex
