#include <gtest/gtest.h>

#include <vector>

#include "coupling/speculative_touches.hpp"

using namespace dexcloth;
using namespace dexcloth::coupling;

namespace {

ContactGroup group(int vertex, int mesh, bool speculative) {
  ContactGroup g;
  g.cloth = 0;
  g.vertex = vertex;
  g.other_mesh = mesh;
  g.speculative = speculative;
  return g;
}

}  // namespace

TEST(SpeculativeTouches, MergedGroupsKeepEachVertexTogetherAndAddOnlyBodiesItDoesNotTouch) {
  // Meshes: 1 a table, 2 and 3 fingers. Vertex 5 lies on the table and finger 2 comes at it;
  // vertex 3 already touches finger 2 (the speculative record of it is dropped) and finger 3
  // comes; vertex 9 touches nothing yet.
  const std::vector<ContactGroup> real{group(5, 1, false), group(3, 2, false)};
  const std::vector<ContactGroup> ahead{group(3, 2, true), group(3, 3, true), group(5, 2, true),
                                        group(9, 3, true)};
  std::vector<ContactGroup> merged;
  merge_speculative_groups(real, ahead, merged);
  ASSERT_EQ(merged.size(), 5u);
  const int expected[5][3] = {{5, 1, 0}, {5, 2, 1}, {3, 2, 0}, {3, 3, 1}, {9, 3, 1}};
  for (std::size_t k = 0; k < merged.size(); ++k) {
    EXPECT_EQ(merged[k].vertex, expected[k][0]) << k;
    EXPECT_EQ(merged[k].other_mesh, expected[k][1]) << k;
    EXPECT_EQ(merged[k].speculative, expected[k][2] != 0) << k;
  }
  EXPECT_EQ(vertex_end(merged, 0), 2u);
  EXPECT_EQ(vertex_end(merged, 2), 4u);
}
