#pragma once
/// Reading JSON text with errors a person can act on: syntax errors as "line L, column C",
/// duplicate keys (which JSON parsers silently collapse) at their JSON pointer.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/errors.hpp"

namespace dexcloth::scene {

/// Parses `text` (comments `//` and `/* */` allowed); problems go to `errors` under `file`.
/// Returns nothing on a syntax error; on duplicate keys returns the document (last value wins)
/// with the duplicates reported.
std::optional<nlohmann::json> parse_json_text(const std::string& text, const std::string& file,
                                              ErrorList& errors);

/// Reads and parses the file at `path` as parse_json_text does; a missing or unreadable file is
/// reported as such.
std::optional<nlohmann::json> read_json_file(const std::string& path, ErrorList& errors);

/// "line L, column C" (both 1-based) of the 1-based byte offset `byte` in `text`.
std::string line_column(const std::string& text, std::size_t byte);

}  // namespace dexcloth::scene
