#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "io/viewer_launch.hpp"
#include "recording_fixtures.hpp"

using namespace dexcloth::io;
using namespace dexcloth::io::testing;
namespace fs = std::filesystem;

namespace {

// Message of the std::runtime_error `f` throws ("" if none).
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// A finished three-frame recording in a fresh folder.
std::string three_frame_recording() {
  const fs::path dir = fresh_dir();
  const dexcloth::io::RecordingHeader h = sample_header();
  RecordingWriter w(dir, h);
  for (int k = 0; k < 3; ++k) w.write_frame(sample_frame(h, k));
  return dir.string();
}

}  // namespace

// Everything below is refused before node is started, so these tests need neither node nor Chromium.

TEST(ViewerLaunch, ViewerDirDefaultsToTheSourceTree) {
  ::unsetenv("DEXCLOTH_VIEWER_DIR");
  EXPECT_EQ(viewer_dir(), fs::path(DEXCLOTH_SOURCE_DIR) / "viewer");
  EXPECT_TRUE(fs::exists(viewer_dir() / "serve.mjs"));
  EXPECT_TRUE(fs::exists(viewer_dir() / "snapshot.mjs"));
}

TEST(ViewerLaunch, RefusesBadRecordingsAndArguments) {
  const std::string dir = three_frame_recording();
  const std::string missing = dir + "/nothing_here";
  EXPECT_NE(error_of([&] { run_viewer_server(missing, 8080); }).find(missing + "/recording.json"),
            std::string::npos);
  EXPECT_NE(error_of([&] { run_viewer_server(dir, 70000); }).find("--port"), std::string::npos);
  EXPECT_NE(error_of([&] { run_snapshot(dir, {0, 3}, dir + "/png", ""); })
                .find("--frames: frame 3 not in"),
            std::string::npos);
  EXPECT_NE(error_of([&] { run_snapshot(dir, {0}, "", ""); }).find("nothing to do"),
            std::string::npos);
  EXPECT_NE(error_of([&] { run_snapshot(dir, {}, dir + "/png", ""); }).find("--frames"),
            std::string::npos);
}

TEST(ViewerLaunch, SaysWhereTheViewerIsMissing) {
  const std::string dir = three_frame_recording();
  ::setenv("DEXCLOTH_VIEWER_DIR", "/nonexistent/viewer", 1);
  const std::string e = error_of([&] { run_viewer_server(dir, 0); });
  ::unsetenv("DEXCLOTH_VIEWER_DIR");
  EXPECT_NE(e.find("/nonexistent/viewer/serve.mjs: viewer not found"), std::string::npos) << e;

  // A viewer folder without node_modules: the message points at scripts/setup.sh.
  const fs::path fake = fresh_dir("_viewer");
  std::ofstream(fake / "serve.mjs") << "\n";
  ::setenv("DEXCLOTH_VIEWER_DIR", fake.c_str(), 1);
  const std::string e2 = error_of([&] { run_viewer_server(dir, 0); });
  ::unsetenv("DEXCLOTH_VIEWER_DIR");
  // Either node is absent or node_modules is: both messages name scripts/setup.sh.
  EXPECT_NE(e2.find("scripts/setup.sh"), std::string::npos) << e2;
}
