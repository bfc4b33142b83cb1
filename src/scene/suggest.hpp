#pragma once
/// "Did you mean" suggestions for misspelt keys and names.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dexcloth::scene {

/// Optimal-string-alignment edit distance (insert, delete, substitute, swap neighbours).
int edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `word` when its edit distance is at most `max_distance` (ties: the
/// first candidate); nothing otherwise.
std::optional<std::string> closest_match(std::string_view word,
                                         const std::vector<std::string_view>& candidates,
                                         int max_distance = 2);

}  // namespace dexcloth::scene
