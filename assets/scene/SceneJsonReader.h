// SceneJsonReader: reads typed values out of the JSON objects of a scene file, each error naming the file,
// the JSON path of the bad value and why (the scene loader's and the joint parser's one way of reading).
// A value type over a parsed document; use from one thread.
#pragma once

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "physics/core/Result.h"
#include "physics/math/Math.h"

namespace strata {

using SceneJson = nlohmann::json;

class SceneJsonReader {
 public:
  SceneJsonReader(const std::string& source, std::string path) : source_(source), path_(std::move(path)) {}

  Error Fail(const std::string& key, const std::string& why) const {
    return MakeError(ErrorCode::kParseError,
                     source_ + ": " + path_ + (key.empty() ? "" : "/" + key) + ": " + why);
  }
  std::string Child(const std::string& key) const { return path_ + "/" + key; }
  SceneJsonReader At(const std::string& key) const { return SceneJsonReader(source_, Child(key)); }
  const std::string& source() const { return source_; }

  // Each getter leaves `out` unchanged when the key is absent and returns an error when present but wrong.
  Status Number(const SceneJson& object, const std::string& key, float& out) const {
    if (!object.contains(key)) return Status::Ok();
    const SceneJson& value = object[key];
    if (!value.is_number()) return Fail(key, "must be a number");
    const double number = value.get<double>();
    if (!std::isfinite(number)) return Fail(key, "must be finite");
    if (std::abs(number) > static_cast<double>(std::numeric_limits<float>::max()))
      return Fail(key, "does not fit a 32-bit float (|x| <= 3.4e38)");
    out = static_cast<float>(number);
    return Status::Ok();
  }
  Status Integer(const SceneJson& object, const std::string& key, int& out) const {
    if (!object.contains(key)) return Status::Ok();
    if (!object[key].is_number_integer()) return Fail(key, "must be an integer");
    // Read wide and range-check: get<int>() would wrap 4294967297 to 1.
    const bool negative = object[key].is_number_unsigned() ? false : object[key].get<std::int64_t>() < 0;
    const double wide = negative ? static_cast<double>(object[key].get<std::int64_t>())
                                 : static_cast<double>(object[key].get<std::uint64_t>());
    if (wide < std::numeric_limits<int>::min() || wide > std::numeric_limits<int>::max())
      return Fail(key, "is out of range for an integer setting");
    out = static_cast<int>(wide);
    return Status::Ok();
  }
  Status Boolean(const SceneJson& object, const std::string& key, bool& out) const {
    if (!object.contains(key)) return Status::Ok();
    if (!object[key].is_boolean()) return Fail(key, "must be true or false");
    out = object[key].get<bool>();
    return Status::Ok();
  }
  Status String(const SceneJson& object, const std::string& key, std::string& out) const {
    if (!object.contains(key)) return Status::Ok();
    if (!object[key].is_string()) return Fail(key, "must be a string");
    out = object[key].get<std::string>();
    return Status::Ok();
  }
  Status Vector(const SceneJson& object, const std::string& key, Vec3& out) const {
    if (!object.contains(key)) return Status::Ok();
    return ParseVector(object[key], key, out);
  }
  Status ParseVector(const SceneJson& value, const std::string& key, Vec3& out) const {
    if (!value.is_array() || value.size() != 3) return Fail(key, "must be an array of 3 numbers");
    for (int i = 0; i < 3; ++i) {
      if (!value[i].is_number() || !std::isfinite(value[i].get<double>()))
        return Fail(key + "/" + std::to_string(i), "must be a finite number");
      if (std::abs(value[i].get<double>()) > static_cast<double>(std::numeric_limits<float>::max()))
        return Fail(key + "/" + std::to_string(i), "does not fit a 32-bit float (|x| <= 3.4e38)");
      out[i] = value[i].get<float>();
    }
    return Status::Ok();
  }
  Status Rotation(const SceneJson& object, const std::string& key, Quat& out) const {
    if (!object.contains(key)) return Status::Ok();
    const SceneJson& value = object[key];
    if (!value.is_array() || value.size() != 4) return Fail(key, "must be a quaternion [w, x, y, z]");
    float q[4];
    for (int i = 0; i < 4; ++i) {
      if (!value[i].is_number() || !std::isfinite(value[i].get<double>()) ||
          std::abs(value[i].get<double>()) > 1e6)
        return Fail(key + "/" + std::to_string(i), "must be a finite number");
      q[i] = value[i].get<float>();
    }
    const Quat rotation(q[0], q[1], q[2], q[3]);
    if (rotation.norm() < 1e-6f) return Fail(key, "must not be the zero quaternion");
    out = rotation.normalized();
    return Status::Ok();
  }
  Status OnlyKeys(const SceneJson& object, std::initializer_list<const char*> allowed) const {
    const std::set<std::string> keys(allowed.begin(), allowed.end());
    for (const auto& [key, value] : object.items())
      if (!keys.count(key)) return Fail(key, "unknown key");
    return Status::Ok();
  }

 private:
  const std::string& source_;
  std::string path_;
};

/// Returns the error of a failed Status from the enclosing function (which returns a Status or a Result):
/// the parsers read a dozen keys in a row, and an early return per key is what this spells.
#define STRATA_TRY(expression)                                           \
  do {                                                                   \
    if (Status status_ = (expression); !status_) return status_.error(); \
  } while (false)

}  // namespace strata
