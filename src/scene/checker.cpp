#include "scene/checker.hpp"

#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/suggest.hpp"

namespace dexcloth::scene {

namespace {

// Shortest readable form of a bound: 0, 0.5, 0.05, 1e-06.
std::string format_bound(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

bool Rule::contains(double x) const {
  if (lo && (lo_strict ? !(x > *lo) : !(x >= *lo))) return false;
  if (hi && (hi_strict ? !(x < *hi) : !(x <= *hi))) return false;
  return true;
}

std::string Rule::describe() const {
  if (lo && hi) {
    return std::string("in ") + (lo_strict ? "(" : "[") + format_bound(*lo) + ", " +
           format_bound(*hi) + (hi_strict ? ")" : "]");
  }
  if (lo) return (lo_strict ? "> " : ">= ") + format_bound(*lo);
  if (hi) return (hi_strict ? "< " : "<= ") + format_bound(*hi);
  return "finite";
}

std::string describe_value(const Json& v) {
  // Long values are cut so one bad array does not flood the report.
  constexpr std::size_t max_chars = 40;
  std::string text;
  if (v.is_array()) return "array of " + std::to_string(v.size());
  if (v.is_object()) return "object";
  text = v.dump();
  if (text.size() > max_chars) text = text.substr(0, max_chars) + "...";
  if (v.is_string()) return "string " + text;
  return text;
}

Checker::Checker(ErrorList& errors, std::string file, std::string base_dir)
    : m_errors(errors), m_file(std::move(file)), m_base_dir(std::move(base_dir)) {}

void Checker::fail(const Pointer& at, std::string message) {
  m_errors.add(m_file, at.to_string(), std::move(message));
}

bool Checker::require_object(const Json& v, const Pointer& at) {
  if (v.is_object()) return true;
  fail(at, "must be an object, got " + describe_value(v));
  return false;
}

bool Checker::require_array(const Json& v, const Pointer& at) {
  if (v.is_array()) return true;
  fail(at, "must be an array, got " + describe_value(v));
  return false;
}

void Checker::check_keys(const Json& obj, const Pointer& at,
                         const std::vector<std::string_view>& allowed) {
  for (const auto& [key, value] : obj.items()) {
    bool known = false;
    for (const auto a : allowed) known = known || key == a;
    if (known) continue;
    std::string message = "unknown key \"" + key + "\"";
    if (const auto guess = closest_match(key, allowed)) {
      message += "; did you mean \"" + *guess + "\"?";
    }
    fail(at / key, message);
  }
}

const Json* Checker::member(const Json& obj, const Pointer& at, std::string_view key, Need need) {
  const std::string k(key);
  const auto it = obj.find(k);
  if (it != obj.end()) return &*it;
  if (need == Need::required) fail(at / k, "required key is missing");
  return nullptr;
}

std::optional<double> Checker::require_number(const Json& v, const Pointer& at, const Rule& rule) {
  if (!v.is_number()) {
    fail(at, "must be a number, got " + describe_value(v));
    return std::nullopt;
  }
  const double x = v.get<double>();
  if (!std::isfinite(x)) {
    fail(at, "must be finite, got " + describe_value(v));
    return std::nullopt;
  }
  if (!rule.contains(x)) {
    fail(at, "must be " + rule.describe() + ", got " + describe_value(v));
    return std::nullopt;
  }
  return x;
}

std::optional<int> Checker::require_int(const Json& v, const Pointer& at, const Rule& rule) {
  // Integral-valued floats (10.0) are accepted: they are exactly an integer.
  const bool integral =
      v.is_number_integer() || (v.is_number_float() && std::isfinite(v.get<double>()) &&
                                std::floor(v.get<double>()) == v.get<double>());
  if (!integral) {
    fail(at, "must be an integer, got " + describe_value(v));
    return std::nullopt;
  }
  const double x = v.get<double>();
  if (x < static_cast<double>(INT_MIN) || x > static_cast<double>(INT_MAX)) {
    fail(at, "integer out of range, got " + describe_value(v));
    return std::nullopt;
  }
  if (!rule.contains(x)) {
    fail(at, "must be " + rule.describe() + ", got " + describe_value(v));
    return std::nullopt;
  }
  return static_cast<int>(x);
}

std::optional<std::string> Checker::require_string(const Json& v, const Pointer& at,
                                                   bool allow_empty) {
  if (!v.is_string()) {
    fail(at, "must be a string, got " + describe_value(v));
    return std::nullopt;
  }
  auto s = v.get<std::string>();
  if (s.empty() && !allow_empty) {
    fail(at, "must not be empty");
    return std::nullopt;
  }
  return s;
}

std::optional<bool> Checker::require_bool(const Json& v, const Pointer& at) {
  if (!v.is_boolean()) {
    fail(at, "must be true or false, got " + describe_value(v));
    return std::nullopt;
  }
  return v.get<bool>();
}

std::optional<Vec3> Checker::require_vec3(const Json& v, const Pointer& at) {
  const auto a = require_numbers<3>(v, at, Rule::any());
  if (!a) return std::nullopt;
  return Vec3((*a)[0], (*a)[1], (*a)[2]);
}

std::optional<std::string> Checker::require_file(const Json& v, const Pointer& at) {
  namespace fs = std::filesystem;
  const auto rel = require_string(v, at, false);
  if (!rel) return std::nullopt;
  // Relative paths are relative to the scene file's folder.
  const fs::path path = (fs::path(m_base_dir) / fs::path(*rel)).lexically_normal();
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    fail(at, "file not found: \"" + path.string() + "\"");
    return std::nullopt;
  }
  if (!fs::is_regular_file(path, ec)) {
    fail(at, "not a regular file: \"" + path.string() + "\"");
    return std::nullopt;
  }
  if (!std::ifstream(path).good()) {
    fail(at, "file cannot be read: \"" + path.string() + "\"");
    return std::nullopt;
  }
  return path.string();
}

bool Checker::number_field(const Json& obj, const Pointer& at, std::string_view key,
                           const Rule& rule, double& out, Need need) {
  const Json* v = member(obj, at, key, need);
  if (!v) return false;
  const auto x = require_number(*v, at / std::string(key), rule);
  if (x) out = *x;
  return x.has_value();
}

bool Checker::vec3_field(const Json& obj, const Pointer& at, std::string_view key, Vec3& out,
                         Need need) {
  const Json* v = member(obj, at, key, need);
  if (!v) return false;
  const auto x = require_vec3(*v, at / std::string(key));
  if (x) out = *x;
  return x.has_value();
}

bool Checker::bool_field(const Json& obj, const Pointer& at, std::string_view key, bool& out,
                         Need need) {
  const Json* v = member(obj, at, key, need);
  if (!v) return false;
  const auto x = require_bool(*v, at / std::string(key));
  if (x) out = *x;
  return x.has_value();
}

bool Checker::string_field(const Json& obj, const Pointer& at, std::string_view key,
                           std::string& out, Need need, bool allow_empty) {
  const Json* v = member(obj, at, key, need);
  if (!v) return false;
  auto x = require_string(*v, at / std::string(key), allow_empty);
  if (x) out = std::move(*x);
  return x.has_value();
}

}  // namespace dexcloth::scene
