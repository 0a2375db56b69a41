// A JSON value with where it sits in its file, for the readers of JSON parameter sets (a scene's
// entries, a material's parameters): every problem they report names the file and the value's JSON
// pointer (RFC 6901), e.g. "scene.json: /materials/gold/alpha: expected a positive number".
// Internal to the library: the public face is btf::MaterialParams (btf/material/material_params.h),
// which keeps nlohmann::json out of the installed headers.
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>

#include <glm/glm.hpp>

#include "btf/core/error.h"
#include "btf/core/rgb.h"

namespace btf::detail {

using nlohmann::json;

// A key as a JSON pointer token (RFC 6901): "~" and "/" are escaped as "~0" and "~1".
inline std::string pointerToken(const std::string& key) {
  std::string out;
  for (const char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

// A JSON value with where it sits in the file, so that every problem names its JSON pointer.
class JsonNode {
 public:
  // Relative paths in the value resolve against `base` when given, else against the file's folder.
  JsonNode(const json& value, std::string pointer, const std::filesystem::path& file,
           const std::filesystem::path* base = nullptr)
      : value_(&value), pointer_(std::move(pointer)), file_(&file), base_(base) {}

  [[noreturn]] void fail(const std::string& problem) const {
    const std::string where = (pointer_.empty() ? std::string("/") : pointer_) + ": " + problem;
    if (file_->empty()) throw Error(where);  // a value made in code: no file to name
    throw FileError(*file_, where);
  }
  const json& value() const { return *value_; }
  const std::string& pointer() const { return pointer_; }
  const std::filesystem::path& file() const { return *file_; }

  bool has(const std::string& key) const { return value_->is_object() && value_->contains(key); }
  JsonNode operator[](const std::string& key) const {
    if (!value_->is_object()) fail("expected an object");
    const auto it = value_->find(key);
    if (it == value_->end()) fail("missing \"" + key + "\"");
    return JsonNode(*it, pointer_ + "/" + pointerToken(key), *file_, base_);
  }
  JsonNode at(std::size_t i) const { return JsonNode((*value_)[i], pointer_ + "/" + std::to_string(i), *file_, base_); }
  std::size_t size() const { return value_->size(); }

  // Keys that are not in `known` are errors: a misspelt key would otherwise be silently ignored.
  void allowOnly(std::initializer_list<const char*> known) const {
    if (!value_->is_object()) fail("expected an object");
    for (const auto& [key, v] : value_->items()) {
      bool ok = false;
      for (const char* k : known) ok = ok || key == k;
      if (!ok) {
        std::string list;
        for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
        JsonNode(v, pointer_ + "/" + pointerToken(key), *file_).fail("unknown key (expected one of: " + list + ")");
      }
    }
  }
  const json::object_t& object() const {
    if (!value_->is_object()) fail("expected an object");
    return value_->get_ref<const json::object_t&>();
  }
  void requireArray() const {
    if (!value_->is_array()) fail("expected an array");
  }

  double number() const {
    if (!value_->is_number()) fail("expected a number, got " + std::string(value_->type_name()));
    const double v = value_->get<double>();
    if (!std::isfinite(v)) fail("expected a finite number");
    return v;
  }
  double number(double lo, double hi, const char* range) const {
    const double v = number();
    if (!(v >= lo && v <= hi)) fail("expected a number " + std::string(range) + ", got " + value_->dump());
    return v;
  }
  double positive() const {
    const double v = number();
    if (!(v > 0)) fail("expected a positive number, got " + value_->dump());
    return v;
  }
  // The same, for values stored as float: checked in that type (1e300 would become inf).
  float floatNumber() const {
    const double v = number();
    if (std::abs(v) > double(std::numeric_limits<float>::max()))
      fail("the number " + value_->dump() + " is beyond the range of a float");
    return float(v);
  }
  float positiveFloat() const {
    const float v = floatNumber();
    if (!(v > 0)) fail("expected a positive number, got " + value_->dump());
    return v;
  }
  int integer(int lo, int hi) const {
    if (!value_->is_number_integer()) fail("expected an integer, got " + value_->dump());
    const long long v = value_->get<long long>();
    if (v < lo || v > hi) fail("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + value_->dump());
    return int(v);
  }
  std::string string() const {
    if (!value_->is_string()) fail("expected a string, got " + std::string(value_->type_name()));
    return value_->get<std::string>();
  }
  bool boolean() const {
    if (!value_->is_boolean()) fail("expected true or false");
    return value_->get<bool>();
  }
  glm::vec3 vec3() const {
    if (!value_->is_array() || value_->size() != 3) fail("expected an array of 3 numbers");
    return {at(0).floatNumber(), at(1).floatNumber(), at(2).floatNumber()};
  }
  // A colour: 3 non-negative numbers, or one number for grey.
  Rgb rgb() const {
    if (value_->is_number()) {
      const float v = floatNumber();
      if (v < 0) fail("a colour must not be negative");
      return Rgb(v);
    }
    const glm::vec3 v = vec3();
    if (v.x < 0 || v.y < 0 || v.z < 0) fail("a colour must not be negative");
    return {v.x, v.y, v.z};
  }
  std::filesystem::path path() const {
    const std::filesystem::path p = string();
    if (p.empty()) fail("expected a file name");
    return p.is_absolute() ? p : (base_ ? *base_ : file_->parent_path()) / p;
  }
  std::filesystem::path existingPath() const {
    const std::filesystem::path p = path();
    std::error_code ec;
    if (!std::filesystem::exists(p, ec)) fail("no such file: " + p.string());
    return p;
  }

 private:
  const json* value_;
  std::string pointer_;
  const std::filesystem::path* file_;
  const std::filesystem::path* base_;
};

}  // namespace btf::detail
