#include "scene/overrides.hpp"

#include <deque>

namespace dexcloth::scene {

namespace {

using Json = nlohmann::json;
using Pointer = Json::json_pointer;

// Array index named by a pointer token: decimal digits without leading zeros.
std::optional<std::size_t> array_index(const std::string& token) {
  if (token.empty() || token.size() > 9) return std::nullopt;
  if (token.size() > 1 && token[0] == '0') return std::nullopt;
  for (const char ch : token) {
    if (ch < '0' || ch > '9') return std::nullopt;
  }
  return static_cast<std::size_t>(std::stoul(token));
}

// The pointer's reference tokens, unescaped, root first.
std::deque<std::string> tokens_of(Pointer p) {
  std::deque<std::string> tokens;
  while (!p.empty()) {
    tokens.push_front(p.back());
    p.pop_back();
  }
  return tokens;
}

// Writes `o.value` at `o.pointer` in `doc`; returns a problem description or "".
std::string write(Json& doc, const Override& o) {
  const auto tokens = tokens_of(o.pointer);
  Pointer here;
  Json* cur = &doc;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const std::string& tok = tokens[i];
    const bool last = i + 1 == tokens.size();
    if (cur->is_object()) {
      // Missing keys become empty objects on the way down; the value lands on the last one.
      if (last) {
        (*cur)[tok] = o.value;
        return "";
      }
      if (!cur->contains(tok)) (*cur)[tok] = Json::object();
      cur = &(*cur)[tok];
    } else if (cur->is_array()) {
      const auto idx = tok == "-" ? std::optional<std::size_t>(cur->size()) : array_index(tok);
      if (!idx) return here.to_string() + " is an array: \"" + tok + "\" is not an index";
      if (last && *idx == cur->size()) {
        cur->push_back(o.value);
        return "";
      }
      if (*idx >= cur->size()) {
        return (here / tok).to_string() + " does not exist: " + here.to_string() + " has " +
               std::to_string(cur->size()) + " entries";
      }
      if (last) {
        (*cur)[*idx] = o.value;
        return "";
      }
      cur = &(*cur)[*idx];
    } else {
      const std::string name = here.empty() ? "the document" : here.to_string();
      return "cannot set inside " + name + ": it is a " + std::string(cur->type_name());
    }
    here /= tok;
  }
  return "";
}

}  // namespace

std::optional<Override> parse_override(const std::string& text, ErrorList& errors) {
  const std::string where = "--set " + text;
  const auto eq = text.find('=');
  if (eq == std::string::npos) {
    errors.add(where, "", "expected /json/pointer=value (no '=' found)");
    return std::nullopt;
  }
  Override o;
  o.text = text;
  // The pointer: "/a/b/0", with ~0 for '~' and ~1 for '/' inside keys.
  try {
    o.pointer = Pointer(text.substr(0, eq));
  } catch (const Json::exception& e) {
    const std::string what = e.what();
    const auto b = what.find("] ");
    errors.add(where, "",
               "invalid JSON pointer: " + (b == std::string::npos ? what : what.substr(b + 2)));
    return std::nullopt;
  }
  if (o.pointer.empty()) {
    errors.add(where, "", "the pointer must name a key, e.g. /dt=0.001");
    return std::nullopt;
  }
  // The value: JSON when it parses, otherwise the text itself as a string.
  const std::string value = text.substr(eq + 1);
  try {
    o.value = Json::parse(value);
  } catch (const Json::parse_error&) {
    o.value = value;
  } catch (const Json::exception&) {
    errors.add(where, "", "number out of range: " + value);
    return std::nullopt;
  }
  return o;
}

Json apply_overrides(Json doc, const std::vector<std::string>& overrides, ErrorList& errors) {
  for (const auto& text : overrides) {
    const auto o = parse_override(text, errors);
    if (!o) continue;
    if (const std::string problem = write(doc, *o); !problem.empty()) {
      errors.add("--set " + text, "", problem);
    }
  }
  return doc;
}

}  // namespace dexcloth::scene
