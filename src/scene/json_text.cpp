#include "scene/json_text.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

namespace dexcloth::scene {

namespace {

using Json = nlohmann::json;

// One open container while parsing: where its children go and which keys it has seen.
struct Frame {
  bool array{false};
  std::size_t index{0};
  std::string key;
  std::set<std::string> keys;
};

// JSON pointer of the current position (the open containers' current keys/indices).
std::string pointer_of(const std::vector<Frame>& stack, std::size_t depth) {
  Json::json_pointer p;
  for (std::size_t i = 0; i < depth; ++i) {
    p = stack[i].array ? p / stack[i].index : p / stack[i].key;
  }
  return p.to_string();
}

// nlohmann messages start "[json.exception...] parse error at line L, column C: "; keep the rest.
std::string strip_prefix(const std::string& what) {
  std::size_t start = 0;
  if (const auto b = what.find("] "); b != std::string::npos) start = b + 2;
  if (const auto pe = what.find("parse error", start); pe == start) {
    if (const auto colon = what.find(": ", pe); colon != std::string::npos) start = colon + 2;
  }
  return what.substr(start);
}

}  // namespace

std::string line_column(const std::string& text, std::size_t byte) {
  // The offending character's 0-based offset, clamped to one past the end of the text.
  const std::size_t pos = std::min(byte == 0 ? 0 : byte - 1, text.size());
  const auto begin = text.begin();
  const auto line = 1 + std::count(begin, begin + static_cast<std::ptrdiff_t>(pos), '\n');
  const auto last_nl = pos == 0 ? std::string::npos : text.rfind('\n', pos - 1);
  const std::size_t column = last_nl == std::string::npos ? pos + 1 : pos - last_nl;
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

std::optional<Json> parse_json_text(const std::string& text, const std::string& file,
                                    ErrorList& errors) {
  // Track open containers so a repeated key can be reported at its JSON pointer.
  std::vector<Frame> stack;
  const Json::parser_callback_t track = [&](int, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    const auto child_done = [&] {
      if (!stack.empty() && stack.back().array) ++stack.back().index;
    };
    switch (event) {
      case E::object_start:
        stack.push_back({});
        break;
      case E::array_start:
        stack.push_back({true, 0, {}, {}});
        break;
      case E::object_end:
      case E::array_end:
        if (!stack.empty()) stack.pop_back();
        child_done();
        break;
      case E::key: {
        Frame& top = stack.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second) {
          errors.add(file, pointer_of(stack, stack.size()),
                     "duplicate key \"" + top.key + "\" (only the last value would be used)");
        }
        break;
      }
      case E::value:
        child_done();
        break;
    }
    return true;
  };
  try {
    return Json::parse(text, track, true, true);
  } catch (const Json::parse_error& e) {
    errors.add(file, line_column(text, e.byte), strip_prefix(e.what()));
  } catch (const Json::exception& e) {
    // Number overflow (1e999) carries no position: locate the literal it quotes.
    const std::string what = e.what();
    const auto q1 = what.find('\'');
    const auto q2 = q1 == std::string::npos ? q1 : what.find('\'', q1 + 1);
    std::string where;
    if (q2 != std::string::npos) {
      const auto at = text.find(what.substr(q1 + 1, q2 - q1 - 1));
      if (at != std::string::npos) where = line_column(text, at + 1);
    }
    errors.add(file, where, strip_prefix(what));
  }
  return std::nullopt;
}

std::optional<Json> read_json_file(const std::string& path, ErrorList& errors) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    errors.add(path, "",
               std::filesystem::exists(path, ec) ? "not a regular file" : "file not found");
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    errors.add(path, "", "cannot open file for reading");
    return std::nullopt;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_json_text(text.str(), path, errors);
}

}  // namespace dexcloth::scene
