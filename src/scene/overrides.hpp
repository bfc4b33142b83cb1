#pragma once
/// Command-line overrides (`--set /json/pointer=value`) applied to a scene document before
/// validation, so an override is checked exactly like the file (a typo is an unknown key).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/errors.hpp"

namespace dexcloth::scene {

/// One parsed `--set` argument.
struct Override {
  std::string text;                      ///< the argument as given, "/dt=0.001"
  nlohmann::json::json_pointer pointer;  ///< where to write, never the whole document
  nlohmann::json value;                  ///< parsed as JSON when it parses, else a plain string
};

/// Parses "/json/pointer=value". The value is JSON when it parses (numbers, arrays, true,
/// "quoted strings"), else a plain string. Malformed arguments are reported under the file name
/// "--set <argument>" and yield nothing.
std::optional<Override> parse_override(const std::string& text, ErrorList& errors);

/// Applies `overrides` in order. Missing object keys along the pointer are created (so a new
/// key is later caught as unknown by validation); array indices must exist, except that the
/// last token may be the array size or "-" to append. Problems go to `errors` under
/// "--set <argument>"; the override is then skipped.
nlohmann::json apply_overrides(nlohmann::json doc, const std::vector<std::string>& overrides,
                               ErrorList& errors);

}  // namespace dexcloth::scene
