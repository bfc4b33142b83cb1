#pragma once
/// Checker: small validation helpers that read JSON values into spec fields and record every
/// problem (with its JSON pointer) in an ErrorList instead of stopping at the first.
#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/errors.hpp"
#include "core/types.hpp"

namespace dexcloth::scene {

using Json = nlohmann::json;
using Pointer = nlohmann::json::json_pointer;

/// Allowed interval for a number: optional lower and upper bounds, each strict or inclusive.
struct Rule {
  std::optional<double> lo;  ///< lower bound, none if unbounded below
  bool lo_strict{false};     ///< `> lo` instead of `>= lo`
  std::optional<double> hi;  ///< upper bound, none if unbounded above
  bool hi_strict{false};     ///< `< hi` instead of `<= hi`

  /// Any finite number.
  static Rule any() { return {}; }
  /// `> 0`.
  static Rule positive() { return {0.0, true, std::nullopt, false}; }
  /// `>= 0`.
  static Rule non_negative() { return {0.0, false, std::nullopt, false}; }
  /// `>= lo`.
  static Rule at_least(double lo) { return {lo, false, std::nullopt, false}; }
  /// An interval with both bounds.
  static Rule between(double lo, bool lo_strict, double hi, bool hi_strict) {
    return {lo, lo_strict, hi, hi_strict};
  }

  /// Whether `x` satisfies the bounds.
  bool contains(double x) const;
  /// "> 0", ">= 2", "in [0, 0.5)".
  std::string describe() const;
};

/// Whether a key must be present.
enum class Need { optional, required };

/// Validation context for one input file: where errors go and how relative paths resolve.
class Checker {
 public:
  /// `file` names the input in messages; `base_dir` resolves relative file paths ("" = cwd).
  Checker(ErrorList& errors, std::string file, std::string base_dir);

  /// Records one problem at `at`.
  void fail(const Pointer& at, std::string message);
  /// Number of problems recorded so far in the shared list.
  std::size_t error_count() const { return m_errors.size(); }

  /// Reports (and returns false) unless `v` is an object.
  bool require_object(const Json& v, const Pointer& at);
  /// Reports (and returns false) unless `v` is an array.
  bool require_array(const Json& v, const Pointer& at);
  /// Reports every key of object `obj` not in `allowed`, suggesting the closest allowed key.
  void check_keys(const Json& obj, const Pointer& at, const std::vector<std::string_view>& allowed);
  /// The value of `key` in object `obj`, or nullptr; reports a missing key when required.
  const Json* member(const Json& obj, const Pointer& at, std::string_view key, Need need);

  /// A finite number satisfying `rule`.
  std::optional<double> require_number(const Json& v, const Pointer& at, const Rule& rule);
  /// An integer (an integral-valued number) that fits an int and satisfies `rule`.
  std::optional<int> require_int(const Json& v, const Pointer& at, const Rule& rule);
  /// A string; empty strings are rejected unless `allow_empty`.
  std::optional<std::string> require_string(const Json& v, const Pointer& at, bool allow_empty);
  /// A boolean.
  std::optional<bool> require_bool(const Json& v, const Pointer& at);
  /// An array of exactly N finite numbers, each satisfying `rule`.
  template <std::size_t N>
  std::optional<std::array<double, N>> require_numbers(const Json& v, const Pointer& at,
                                                       const Rule& rule);
  /// An array of exactly N integers, each satisfying `rule`.
  template <std::size_t N>
  std::optional<std::array<int, N>> require_ints(const Json& v, const Pointer& at,
                                                 const Rule& rule);
  /// [x, y, z], finite.
  std::optional<Vec3> require_vec3(const Json& v, const Pointer& at);
  /// A path to an existing, readable regular file; returns it resolved against the base folder.
  std::optional<std::string> require_file(const Json& v, const Pointer& at);

  /// Field readers: an absent optional key keeps `out` (its default); a present key must be
  /// valid. Return true when the key is present and valid.
  bool number_field(const Json& obj, const Pointer& at, std::string_view key, const Rule& rule,
                    double& out, Need need = Need::optional);
  /// See number_field.
  bool vec3_field(const Json& obj, const Pointer& at, std::string_view key, Vec3& out,
                  Need need = Need::optional);
  /// See number_field.
  bool bool_field(const Json& obj, const Pointer& at, std::string_view key, bool& out,
                  Need need = Need::optional);
  /// See number_field; `allow_empty` as in require_string.
  bool string_field(const Json& obj, const Pointer& at, std::string_view key, std::string& out,
                    Need need = Need::optional, bool allow_empty = false);

 private:
  ErrorList& m_errors;
  std::string m_file;
  std::string m_base_dir;
};

/// Short description of a JSON value for messages: `string "abc"`, `-1`, `array of 2`, ...
std::string describe_value(const Json& v);

template <std::size_t N>
std::optional<std::array<double, N>> Checker::require_numbers(const Json& v, const Pointer& at,
                                                              const Rule& rule) {
  if (!v.is_array() || v.size() != N) {
    fail(at, "must be an array of " + std::to_string(N) + " numbers, got " + describe_value(v));
    return std::nullopt;
  }
  std::array<double, N> out{};
  bool ok = true;
  for (std::size_t i = 0; i < N; ++i) {
    const auto x = require_number(v[i], at / i, rule);
    ok = ok && x.has_value();
    if (x) out[i] = *x;
  }
  if (!ok) return std::nullopt;
  return out;
}

template <std::size_t N>
std::optional<std::array<int, N>> Checker::require_ints(const Json& v, const Pointer& at,
                                                        const Rule& rule) {
  if (!v.is_array() || v.size() != N) {
    fail(at, "must be an array of " + std::to_string(N) + " integers, got " + describe_value(v));
    return std::nullopt;
  }
  std::array<int, N> out{};
  bool ok = true;
  for (std::size_t i = 0; i < N; ++i) {
    const auto x = require_int(v[i], at / i, rule);
    ok = ok && x.has_value();
    if (x) out[i] = *x;
  }
  if (!ok) return std::nullopt;
  return out;
}

}  // namespace dexcloth::scene
