/// JSON text reading: line/column of syntax errors, comments, duplicate keys at their pointer.
#include <gtest/gtest.h>

#include "scene/json_text.hpp"
#include "scene_test_util.hpp"

namespace dexcloth::scene::test {
namespace {

TEST(LineColumn, CountsFromOne) {
  const std::string text = "ab\ncd\n";
  EXPECT_EQ(line_column(text, 1), "line 1, column 1");
  EXPECT_EQ(line_column(text, 2), "line 1, column 2");
  EXPECT_EQ(line_column(text, 4), "line 2, column 1");
  EXPECT_EQ(line_column(text, 5), "line 2, column 2");
  // Past the end (unexpected end of input): the position after the last character.
  EXPECT_EQ(line_column(text, 7), "line 3, column 1");
}

TEST(ParseJsonText, SyntaxErrorNamesLineAndColumn) {
  ErrorList errors;
  const auto doc = parse_json_text("{\n  \"a\": 1,\n  \"b\" 2\n}", "x.json", errors);
  EXPECT_FALSE(doc);
  expect_errors(errors, {{"x.json", "line 3, column 7", "expected ':'"}});
}

TEST(ParseJsonText, UnexpectedEndOfInput) {
  ErrorList errors;
  EXPECT_FALSE(parse_json_text("{\"a\": [1, 2", "x.json", errors));
  expect_errors(errors, {{"x.json", "line 1, column 12", "unexpected end of input"}});
}

TEST(ParseJsonText, AllowsComments) {
  ErrorList errors;
  const auto doc = parse_json_text("{ // note\n \"a\": /* inline */ 1 }", "x.json", errors);
  ASSERT_TRUE(doc);
  EXPECT_TRUE(errors.empty());
  EXPECT_EQ((*doc)["a"], 1);
}

TEST(ParseJsonText, DuplicateKeysAtTheirPointer) {
  ErrorList errors;
  const auto doc = parse_json_text(
      R"({"a": [0, {"k": 1}, [2], {"k": 1, "k": 2}], "b": {"x~y/z": 1, "x~y/z": 2}, "a": 3})",
      "x.json", errors);
  ASSERT_TRUE(doc);
  expect_errors(errors, {{"x.json", "/a/3/k", "duplicate key \"k\""},
                         {"x.json", "/b/x~0y~1z", "duplicate key \"x~y/z\""},
                         {"x.json", "/a", "duplicate key \"a\""}});
}

}  // namespace
}  // namespace dexcloth::scene::test
