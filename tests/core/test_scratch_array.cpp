#include <gtest/gtest.h>

#include "core/scratch_array.hpp"

using dexcloth::ScratchArray;

TEST(ScratchArray, ResizesWithoutReallocatingWithinItsHeadroom) {
  ScratchArray a;
  EXPECT_EQ(a.size(), 0u);
  a.resize(1000);
  ASSERT_NE(a.data(), nullptr);
  EXPECT_EQ(a.size(), 1000u);
  for (std::size_t k = 0; k < a.size(); ++k) a.data()[k] = static_cast<double>(k);  // writable
  const double* first = a.data();
  a.resize(10);  // shrinking keeps the storage
  EXPECT_EQ(a.size(), 10u);
  EXPECT_EQ(a.data(), first);
  a.resize(1250);  // growing within the quarter of headroom keeps it too
  EXPECT_EQ(a.size(), 1250u);
  EXPECT_EQ(a.data(), first);
  a.resize(1251);  // beyond it, new storage
  EXPECT_EQ(a.size(), 1251u);
  a.data()[1250] = 1.0;
  const ScratchArray& view = a;
  EXPECT_EQ(view.data()[1250], 1.0);
}
