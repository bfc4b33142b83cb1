#include "cli_runner.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "io/recording.hpp"

namespace dexcloth::test {

CliResult run_cli(const std::string& args, const std::string& prefix) {
  const std::string cmd = prefix + "\"" + DEXCLOTH_EXE + "\" " + args + " 2>&1";
  CliResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) throw std::runtime_error("popen failed: " + cmd);
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe)) r.output += buf.data();
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::filesystem::path fresh_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string test = info ? std::string(info->test_suite_name()) + "_" + info->name() : "t";
  // Under this build tree, so that two builds' suites run at once do not share outputs.
  auto dir =
      std::filesystem::path(DEXCLOTH_BINARY_DIR) / "test_output" / "app" / (test + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir.parent_path());
  return dir;
}

nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path.string());
  return nlohmann::json::parse(f);
}

std::filesystem::path source_dir() { return DEXCLOTH_SOURCE_DIR; }

CliRun run_file(const std::filesystem::path& scene, const std::string& name,
                const std::string& args) {
  CliRun run;
  run.out = fresh_dir(name);
  const auto r =
      run_cli("run " + scene.string() + " --quiet --out " + run.out.string() + " " + args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  run.summary = read_json(run.out / "summary.json");
  return run;
}

nlohmann::json run_scene(const std::string& name, const std::string& args) {
  return run_file(source_dir() / "scenes" / (name + ".json"), name, args).summary;
}

double probe_distance(const nlohmann::json& a, const nlohmann::json& b) {
  double sum = 0.0;
  for (int i = 1; i <= 3; ++i) {
    const double d = a[i].get<double>() - b[i].get<double>();
    sum += d * d;
  }
  return std::sqrt(sum);
}

dexcloth::Vec3 probe_at(const nlohmann::json& s, const std::string& probe, double t) {
  const auto& rows = s["probes"][probe];
  std::size_t k = 0;
  while (k + 1 < rows.size() && rows[k][0].get<double>() < t - 1e-9) ++k;
  return {rows[k][1].get<double>(), rows[k][2].get<double>(), rows[k][3].get<double>()};
}

double relative_motion(const nlohmann::json& s, const std::string& moving,
                       const std::string& reference, double t0, double t1) {
  const auto offset = [&](double t) -> dexcloth::Vec3 {
    return probe_at(s, moving, t) - probe_at(s, reference, t);
  };
  return (offset(t1) - offset(t0)).norm();
}

Carry carry(const nlohmann::json& s, const std::string& pinched, double release) {
  const auto& p = s["probes"][pinched];
  const auto& thumb = s["probes"]["thumb_tip"];
  const auto& index = s["probes"]["index_pad"];
  EXPECT_EQ(p.size(), thumb.size()) << pinched;
  EXPECT_EQ(p.size(), index.size()) << pinched;
  Carry out;
  if (p.empty() || p.size() != thumb.size() || p.size() != index.size()) return out;
  double z_release = p[0][3].get<double>();
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double t = p[k][0].get<double>();
    if (t <= release + 1e-9) z_release = p[k][3].get<double>();
    if (t >= release - 1e-9)
      out.farthest =
          std::max({out.farthest, probe_distance(p[k], thumb[k]), probe_distance(p[k], index[k])});
  }
  out.rise = p.back()[3].get<double>() - z_release;
  return out;
}

void expect_intact(const nlohmann::json& s) {
  EXPECT_EQ(s["intersections_max"], 0);
  EXPECT_EQ(s["nan"], false);
  for (const auto& w : s["warnings"])
    EXPECT_EQ(w["message"].get<std::string>().find("lost"), std::string::npos) << w;
}

std::vector<ClothFrame> cloth_frames(const std::filesystem::path& out, int cloth,
                                     dexcloth::Triangles* faces) {
  const dexcloth::io::RecordingReader reader(out / "recording");
  if (faces) *faces = reader.header().cloths.at(static_cast<std::size_t>(cloth)).faces;
  std::vector<ClothFrame> frames;
  for (long k = 0; k < reader.frame_count(); ++k) {
    auto frame = reader.read_frame(k);
    frames.push_back(
        {frame.t, std::move(frame.cloth_positions.at(static_cast<std::size_t>(cloth)))});
  }
  return frames;
}

Heights heights_at(const std::vector<ClothFrame>& frames, double t) {
  for (const ClothFrame& f : frames)
    if (f.t >= t - 1e-9) return {f.x.col(2).minCoeff(), f.x.col(2).maxCoeff(), f.x.col(2).mean()};
  ADD_FAILURE() << "no frame at or after t = " << t;
  return {};
}

}  // namespace dexcloth::test
