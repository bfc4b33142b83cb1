#pragma once
/// Runs the dexcloth executable in tests and captures its exit code and output.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "core/types.hpp"

namespace dexcloth::test {

struct CliResult {
  int exit_code{-1};
  std::string output;  ///< stdout and stderr together
};

/// Runs `dexcloth <args>` (args already shell-quoted where needed), after the shell words
/// `prefix` (e.g. "cd /tmp && NAME=value ").
CliResult run_cli(const std::string& args, const std::string& prefix = "");

/// A fresh, empty folder under the build tree (test_output/app), unique to this test and name.
std::filesystem::path fresh_dir(const std::string& name);

/// Reads a JSON file.
nlohmann::json read_json(const std::filesystem::path& path);

/// Repository root (for scenes/ and tests data).
std::filesystem::path source_dir();

/// A finished run: its summary.json and its output folder (for the recording).
struct CliRun {
  nlohmann::json summary;
  std::filesystem::path out;
};

/// Runs the scene file `scene` through the CLI with extra arguments into fresh_dir(`name`); a
/// non-zero exit fails the test.
CliRun run_file(const std::filesystem::path& scene, const std::string& name,
                const std::string& args = "");

/// run_file on scenes/<name>.json; returns its summary.json.
nlohmann::json run_scene(const std::string& name, const std::string& args = "");

/// Distance between two probe samples [t, x, y, z] [m].
double probe_distance(const nlohmann::json& a, const nlohmann::json& b);

/// Probe `probe`'s position at the first sample of summary `s` at or after t [s] (the last
/// sample when t is past the end) [m].
dexcloth::Vec3 probe_at(const nlohmann::json& s, const std::string& probe, double t);

/// How far probe `moving` moved relative to probe `reference` (both recorded at the same
/// frames) between the first frames at or after t0 and t1 [s] of summary `s` [m].
double relative_motion(const nlohmann::json& s, const std::string& moving,
                       const std::string& reference, double t0, double t1);

/// A hand's carry of a pinched cloth vertex: how far probe `pinched` got from the pad probes
/// `thumb_tip` and `index_pad` at any frame from `release` [s] on, and how much it rose from its
/// last frame at or before `release` to the end [m].
struct Carry {
  double farthest{};
  double rise{};
};
Carry carry(const nlohmann::json& s, const std::string& pinched, double release);

/// One recorded frame of a cloth: simulated time [s] and vertex positions [m].
struct ClothFrame {
  double t{};
  dexcloth::Points x;
};

/// Every recorded frame of cloth `cloth` (header order) in the run folder `out`, and the
/// cloth's faces in `faces` if given.
std::vector<ClothFrame> cloth_frames(const std::filesystem::path& out, int cloth = 0,
                                     dexcloth::Triangles* faces = nullptr);

/// Lowest, highest and mean height (z) of a cloth's vertices [m].
struct Heights {
  double min{}, max{}, mean{};
};

/// The heights at the first of `frames` at or after t [s] (a test failure if there is none).
Heights heights_at(const std::vector<ClothFrame>& frames, double t);

/// Expects a run's summary to show no cloth–cloth or cloth–body intersection at any recorded
/// frame, no NaN, and no warning of lost state.
void expect_intact(const nlohmann::json& s);

}  // namespace dexcloth::test
