#include "json_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "soltex/common/quoted_text.h"
#include "soltex/scene/scene_error.h"

namespace soltex {
namespace {

std::string describe_type(const nlohmann::json& json) {
  if (json.is_number()) return "a number";
  if (json.is_string()) return "a string";
  if (json.is_boolean()) return "a boolean";
  if (json.is_object()) return "an object";
  if (json.is_array()) return "an array";
  return "null";
}

std::string range_text(double lo, double hi) {
  // Appended piece by piece: "[" + std::string&& trips a GCC 12 -Wrestrict false positive.
  std::string text = "[";
  text += format_number(lo);
  text += ", ";
  text += format_number(hi);
  text += "]";
  return text;
}

}  // namespace

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

void JsonValue::fail(const std::string& problem) const {
  throw SceneError(*file_, path_, problem);
}

void JsonValue::expect(bool ok, const char* what) const {
  if (!ok) fail(std::string("expected ") + what + ", found " + describe_type(*json_));
}

double JsonValue::number(double lo, double hi) const {
  expect(json_->is_number(), "a number");
  const double value = json_->get<double>();
  if (!std::isfinite(value)) fail(format_number(value) + " is not finite");
  if (value < lo || value > hi) {
    fail(format_number(value) + " is out of range: must be in " + range_text(lo, hi));
  }
  return value;
}

int JsonValue::integer(int lo, int hi) const {
  expect(json_->is_number(), "an integer");
  const double value = json_->get<double>();
  if (!std::isfinite(value) || value != std::floor(value)) {
    fail(format_number(value) + " is not an integer");
  }
  if (value < lo || value > hi) {
    fail(format_number(value) + " is out of range: must be in " + range_text(lo, hi));
  }
  return static_cast<int>(value);
}

bool JsonValue::boolean() const {
  expect(json_->is_boolean(), "true or false");
  return json_->get<bool>();
}

std::string JsonValue::string() const {
  expect(json_->is_string(), "a string");
  return json_->get<std::string>();
}

glm::dvec3 JsonValue::vec3(double lo, double hi) const {
  glm::dvec3 result;
  if (json_->is_array()) {
    if (json_->size() != 3) {
      fail("expected 3 numbers [x, y, z], found " + std::to_string(json_->size()));
    }
    for (int axis = 0; axis < 3; ++axis) result[axis] = element(axis).number(lo, hi);
    return result;
  }
  expect(json_->is_object(), "[x, y, z] or {\"x\", \"y\", \"z\"}");
  JsonObject object(*this);
  result = {object.get("x").number(lo, hi), object.get("y").number(lo, hi),
            object.get("z").number(lo, hi)};
  object.reject_unknown_keys();
  return result;
}

glm::vec3 JsonValue::colour() const {
  glm::vec3 result;
  if (json_->is_array()) {
    if (json_->size() != 3) {
      fail("expected 3 numbers [r, g, b], found " + std::to_string(json_->size()));
    }
    for (int c = 0; c < 3; ++c) result[c] = static_cast<float>(element(c).number(0.0, 1.0));
    return result;
  }
  expect(json_->is_object(), "[r, g, b] or {\"r\", \"g\", \"b\"}");
  JsonObject object(*this);
  result = {static_cast<float>(object.get("r").number(0.0, 1.0)),
            static_cast<float>(object.get("g").number(0.0, 1.0)),
            static_cast<float>(object.get("b").number(0.0, 1.0))};
  object.reject_unknown_keys();
  return result;
}

std::vector<JsonValue> JsonValue::elements(std::size_t max_count) const {
  expect(json_->is_array(), "an array");
  if (json_->size() > max_count) {
    fail(std::to_string(json_->size()) + " elements: at most " + std::to_string(max_count));
  }
  std::vector<JsonValue> result;
  result.reserve(json_->size());
  for (std::size_t i = 0; i < json_->size(); ++i) result.push_back(element(i));
  return result;
}

JsonValue JsonValue::child(const std::string& key) const {
  // The key may be the client's own (an unknown field, a graph input's name): shown bounded.
  const std::string shown = escaped_text(key);
  return JsonValue(json_->at(key), path_.empty() ? shown : path_ + "." + shown, *file_);
}

JsonValue JsonValue::element(std::size_t index) const {
  return JsonValue(json_->at(index), path_ + "[" + std::to_string(index) + "]", *file_);
}

JsonObject::JsonObject(const JsonValue& value) : value_(value) {
  value_.expect(value_.json().is_object(), "an object");
}

std::optional<JsonValue> JsonObject::find(const char* key) {
  known_.emplace_back(key);
  if (!has(key)) return std::nullopt;
  return value_.child(key);
}

JsonValue JsonObject::get(const char* key) {
  std::optional<JsonValue> found = find(key);
  if (!found) {
    const std::string& path = value_.path();
    throw SceneError(value_.file(), path.empty() ? key : path + "." + key,
                     "missing required field");
  }
  return *found;
}

double JsonObject::number(const char* key, double fallback, double lo, double hi) {
  const std::optional<JsonValue> found = find(key);
  return found ? found->number(lo, hi) : fallback;
}

int JsonObject::integer(const char* key, int fallback, int lo, int hi) {
  const std::optional<JsonValue> found = find(key);
  return found ? found->integer(lo, hi) : fallback;
}

bool JsonObject::boolean(const char* key, bool fallback) {
  const std::optional<JsonValue> found = find(key);
  return found ? found->boolean() : fallback;
}

glm::dvec3 JsonObject::vec3(const char* key, const glm::dvec3& fallback, double lo, double hi) {
  const std::optional<JsonValue> found = find(key);
  return found ? found->vec3(lo, hi) : fallback;
}

glm::vec3 JsonObject::colour(const char* key, const glm::vec3& fallback) {
  const std::optional<JsonValue> found = find(key);
  return found ? found->colour() : fallback;
}

std::size_t JsonObject::one_of(std::initializer_list<const char*> choices,
                               std::initializer_list<const char*> other_fields) {
  std::string names;
  std::vector<std::size_t> present;
  std::size_t index = 0;
  for (const char* key : other_fields) known_.emplace_back(key);
  for (const char* key : choices) {
    known_.emplace_back(key);
    names += (names.empty() ? "" : ", ") + std::string(key);
    if (has(key)) present.push_back(index);
    ++index;
  }
  if (present.size() == 1) return present.front();
  if (present.empty()) {
    // An unknown key here is most likely a misspelt choice: name it.
    for (const auto& item : value_.json().items()) {
      if (std::find(known_.begin(), known_.end(), item.key()) == known_.end()) {
        value_.child(item.key()).fail("unknown field: expected one of " + names);
      }
    }
    value_.fail("expected one of " + names);
  }
  value_.fail("only one of " + names + " may be given");
}

void JsonObject::reject_unknown_keys() const {
  for (const auto& item : value_.json().items()) {
    if (std::find(known_.begin(), known_.end(), item.key()) != known_.end()) continue;
    std::string expected;
    for (const std::string& key : known_) expected += (expected.empty() ? "" : ", ") + key;
    value_.child(item.key())
        .fail("unknown field" + (expected.empty() ? std::string(" (no fields allowed here)")
                                                  : ": expected one of " + expected));
  }
}

}  // namespace soltex
