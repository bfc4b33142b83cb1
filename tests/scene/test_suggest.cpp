/// Edit distance and "did you mean" suggestions.
#include <gtest/gtest.h>

#include "scene/suggest.hpp"

namespace dexcloth::scene {
namespace {

TEST(EditDistance, CountsEdits) {
  EXPECT_EQ(edit_distance("density", "density"), 0);
  EXPECT_EQ(edit_distance("densty", "density"), 1);    // deletion
  EXPECT_EQ(edit_distance("densitty", "density"), 1);  // insertion
  EXPECT_EQ(edit_distance("densiyt", "density"), 1);   // swapped neighbours
  EXPECT_EQ(edit_distance("dnesity", "density"), 1);
  EXPECT_EQ(edit_distance("", "abc"), 3);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3);
}

TEST(ClosestMatch, OnlyWithinTwoEdits) {
  const std::vector<std::string_view> keys = {"density", "damping", "friction"};
  EXPECT_EQ(closest_match("densty", keys), "density");
  EXPECT_EQ(closest_match("frction", keys), "friction");
  EXPECT_EQ(closest_match("dampnig", keys), "damping");
  EXPECT_FALSE(closest_match("weight", keys));
  EXPECT_FALSE(closest_match("dens", keys));  // four deletions away
}

}  // namespace
}  // namespace dexcloth::scene
