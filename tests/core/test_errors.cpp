#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "core/warnings.hpp"

using namespace dexcloth;

TEST(Errors, FormatsFilePointerAndMessage) {
  ErrorList list;
  list.add("scene.json", "/cloths/0/material/density", "must be > 0, got -1");
  list.add("scene.json", "", "not valid JSON");
  EXPECT_EQ(list.errors()[0].to_string(), "scene.json: /cloths/0/material/density: must be > 0, got -1");
  EXPECT_EQ(list.to_string(),
            "scene.json: /cloths/0/material/density: must be > 0, got -1\nscene.json: not valid JSON\n");
}

TEST(Warnings, CapsStoredEntriesButCountsAll) {
  WarningLog log;
  for (std::size_t i = 0; i < WarningLog::capacity() + 5; ++i) log.add(static_cast<long>(i), "w");
  EXPECT_EQ(log.entries().size(), WarningLog::capacity());
  EXPECT_EQ(log.count(), static_cast<long>(WarningLog::capacity() + 5));
  EXPECT_EQ(log.entries()[3].step, 3);
}
