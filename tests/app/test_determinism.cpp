/// Same input, same output: a run's recording and summary do not depend on the output path, the
/// working directory, the order of the arguments, the environment or the number of threads. They
/// did: DART rebuilt the resized patch boxes' collision objects in the order of their skeletons'
/// heap addresses, which the length of the output path changed, and pinch_napkin diverged at 2.7 s.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "cli_runner.hpp"

using namespace dexcloth::test;

namespace {

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  EXPECT_TRUE(f.good()) << path;
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// frames.bin of a recording folder with each record's wall-clock field (step_ms) and the CRC
/// that covers it zeroed: every other byte is simulation output (docs/recording-format.md).
std::string frames_without_timings(std::string bytes) {
  constexpr std::size_t kFileHeader = 16, kRecordHeader = 40, kStepMs = 32;
  EXPECT_GE(bytes.size(), kFileHeader);
  std::size_t at = kFileHeader;
  while (at + kRecordHeader <= bytes.size()) {
    std::uint32_t record_bytes = 0;
    std::memcpy(&record_bytes, bytes.data() + at + 4, sizeof record_bytes);
    if (record_bytes < kRecordHeader + 4 || at + record_bytes > bytes.size()) break;
    std::memset(bytes.data() + at + kStepMs, 0, sizeof(double));
    std::memset(bytes.data() + at + record_bytes - 4, 0, 4);
    at += record_bytes;
  }
  EXPECT_EQ(at, bytes.size()) << "frames.bin does not end on a whole record";
  return bytes;
}

/// summary.json without its wall-clock figures and thread count.
nlohmann::json without_timings(nlohmann::json summary) {
  summary.erase("timing_s");
  summary.erase("step_ms");
  summary.erase("threads");
  return summary;
}

/// Index of the first differing byte, or −1.
long first_difference(const std::string& a, const std::string& b) {
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i)
    if (a[i] != b[i]) return static_cast<long>(i);
  return a.size() == b.size() ? -1 : static_cast<long>(n);
}

}  // namespace

TEST(Determinism, OnlyTheWallClockFieldsOfARecordingAreIgnored) {
  const auto out = fresh_dir("short");
  const auto r = run_cli("run " + (source_dir() / "scenes" / "gripper_pinch.json").string() +
                         " --quiet --duration 0.1 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string frames = read_bytes(out / "recording" / "frames.bin");
  ASSERT_GT(frames.size(), 16u + 44u);
  const std::string masked = frames_without_timings(frames);
  // A changed step_ms of the first record (whose CRC then no longer matches) is ignored...
  constexpr std::size_t kStepMsByte = 16 + 33, kFirstVertexByte = 16 + 41;
  std::string clock_only = frames;
  clock_only[kStepMsByte] = static_cast<char>(clock_only[kStepMsByte] ^ 0x5a);
  EXPECT_EQ(first_difference(frames_without_timings(clock_only), masked), -1);
  // ...a changed vertex position is not.
  std::string moved = frames;
  moved[kFirstVertexByte] = static_cast<char>(moved[kFirstVertexByte] ^ 0x5a);
  EXPECT_EQ(first_difference(frames_without_timings(moved), masked),
            static_cast<long>(kFirstVertexByte));
}

TEST(Determinism, APinchRunIsTheSameWhateverThePathDirectoryArgumentOrderOrEnvironment) {
  const std::string scene = (source_dir() / "scenes" / "pinch_napkin.json").string();
  // Each run in its own working directory; `out` relative to it.
  const auto run = [&](const std::string& name, const std::string& args, const std::string& env) {
    const auto cwd = fresh_dir(name);
    std::filesystem::create_directories(cwd);
    const auto r = run_cli(args, "cd " + cwd.string() + " && " + env);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return cwd;
  };
  // A short output path (a string short enough to need no heap block), a long one (these two
  // gave different runs before the fix), and the arguments reordered with two no-op overrides,
  // a large extra environment variable and two threads instead of one.
  const std::string long_out = "a_much_longer_output_path_than_the_first/with/levels";
  const auto a = run("a", "run " + scene + " --quiet --threads 1 --out n1", "") / "n1";
  const auto b = run("b", "run " + scene + " --threads 1 --quiet --out " + long_out, "") / long_out;
  const auto c = run("c",
                     "run --threads 2 --set /bodies/0/friction=0.5 --out " + long_out +
                         " --set /cloths/0/material/friction=0.5 --quiet " + scene,
                     "DEXCLOTH_DETERMINISM_PADDING=" + std::string(3000, 'x') + " ") /
                 long_out;

  const std::string frames_a = frames_without_timings(read_bytes(a / "recording" / "frames.bin"));
  EXPECT_GT(frames_a.size(), 100000u);
  for (const auto& other : {b, c}) {
    EXPECT_EQ(without_timings(read_json(a / "summary.json")),
              without_timings(read_json(other / "summary.json")))
        << other;
    EXPECT_EQ(read_json(other / "summary.json")["threads"], other == c ? 2 : 1);
    EXPECT_EQ(read_bytes(a / "recording" / "recording.json"),
              read_bytes(other / "recording" / "recording.json"))
        << other;
    EXPECT_EQ(first_difference(
                  frames_a, frames_without_timings(read_bytes(other / "recording" / "frames.bin"))),
              -1)
        << other << ": frames.bin differs from this byte on";
  }
}
