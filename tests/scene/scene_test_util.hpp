#pragma once
/// Shared helpers for the scene tests: data paths and "rejected with exactly these errors".
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/errors.hpp"

namespace dexcloth::scene::test {

/// Path of a file under tests/scene/data/.
inline std::string data_path(const std::string& name) {
  return std::string(DEXCLOTH_SOURCE_DIR) + "/tests/scene/data/" + name;
}

/// One expected problem: exact location (file and pointer) and a fragment of the message.
struct Expected {
  std::string file;      ///< exact InputError::file
  std::string pointer;   ///< exact InputError::pointer
  std::string fragment;  ///< must occur in InputError::message
};

/// Checks that `errors` holds exactly the `expected` problems (any order), and that each one's
/// printed form names the file and the pointer.
inline void expect_errors(const ErrorList& errors, const std::vector<Expected>& expected) {
  EXPECT_EQ(errors.size(), expected.size()) << errors.to_string();
  for (const auto& want : expected) {
    bool found = false;
    for (const auto& e : errors.errors()) {
      if (e.file == want.file && e.pointer == want.pointer &&
          e.message.find(want.fragment) != std::string::npos) {
        found = true;
        const std::string where =
            want.pointer.empty() ? want.file : want.file + ": " + want.pointer;
        EXPECT_EQ(e.to_string().rfind(where + ": ", 0), 0u) << e.to_string();
      }
    }
    EXPECT_TRUE(found) << "missing error " << want.file << ": " << want.pointer << ": ..."
                       << want.fragment << "...\ngot:\n"
                       << errors.to_string();
  }
}

}  // namespace dexcloth::scene::test
