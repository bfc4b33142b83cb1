#include "run_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cloth/collision/intersection.hpp"
#include "core/errors.hpp"
#include "coupling/step.hpp"
#include "progress.hpp"
#include "recorder.hpp"
#include "scene/compile.hpp"
#include "scene/load.hpp"

namespace dexcloth::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Loads, applies CLI overrides, validates and compiles; prints every problem on failure.
bool load_and_compile(const std::string& path, std::vector<std::string> overrides,
                      const RunOptions* run, scene::SceneSpec& spec,
                      scene::CompiledScene& compiled) {
  if (run != nullptr) {
    if (run->duration >= 0.0) overrides.push_back("/duration=" + std::to_string(run->duration));
    if (!run->coupling.empty()) overrides.push_back("/coupling=\"" + run->coupling + "\"");
  }
  try {
    spec = scene::load_scene(path, overrides);
    compiled = scene::compile_scene(spec);
    return true;
  } catch (const InputRejected& e) {
    std::fprintf(stderr, "%s", e.what());
    std::fprintf(stderr, "dexcloth: %s: %zu problem(s); nothing was run\n", path.c_str(),
                 e.errors().size());
    return false;
  }
}

/// What the run records at every frame: probe trajectories [[t, x, y, z], ...] and maxima.
struct FrameLog {
  std::vector<std::vector<std::array<double, 4>>> samples;
  int intersections_max{};
  int contacts_max{};
  int patches_max{};
  int vr_max{};
  std::vector<collision::Bvh> trees;  // of the intersection count, refit from frame to frame
};

/// Number of intersecting triangle pairs (cloth–cloth, cloth–rigid) in the state collision
/// handling resolved.
int count_intersections(coupling::WorldData& data, std::vector<collision::Bvh>& trees) {
  std::vector<const collision::CollisionMesh*> meshes;
  for (const collision::CollisionMesh& m : data.meshes) meshes.push_back(&m);
  return collision::count_intersections(meshes, /*use_x1=*/true, trees, data.pool.get());
}

void record_frame(const scene::CompiledScene& compiled, coupling::WorldData& data,
                  FrameLog& log) {
  log.samples.resize(compiled.probes.size());
  for (std::size_t p = 0; p < compiled.probes.size(); ++p) {
    const scene::CompiledProbe& probe = compiled.probes[p];
    const Vec3 x = probe.cloth >= 0 ? Vec3(data.cloths[probe.cloth].x.row(probe.vertex).transpose())
                                    : data.rigid.world->probe_W(probe.body, probe.point);
    log.samples[p].push_back({data.time, x.x(), x.y(), x.z()});
  }
  if (data.step > 0)
    log.intersections_max = std::max(log.intersections_max, count_intersections(data, log.trees));
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

json make_summary(const scene::SceneSpec& spec, const scene::CompiledScene& compiled,
                  const std::vector<double>& step_ms, const FrameLog& probes) {
  const coupling::WorldData& data = compiled.data;
  json s;
  s["scene"] = spec.name;
  s["coupling"] = spec.coupling.mode;
  s["dt"] = spec.dt;
  s["steps"] = data.step;
  s["threads"] = compiled.model.threads;
  long vertices = 0, triangles = 0;
  for (const auto& body : compiled.model.cloths) {
    vertices += body.x_rest.rows();
    triangles += body.model.faces.rows();
  }
  s["cloth"] = {{"vertices", vertices}, {"triangles", triangles}};
  s["timing_s"] = {{"cloth", data.timings.cloth},
                   {"rigid", data.timings.rigid},
                   {"interface", data.timings.interface},
                   {"total", data.timings.total}};
  const double max_ms = step_ms.empty() ? 0.0 : *std::max_element(step_ms.begin(), step_ms.end());
  s["step_ms"] = {{"median", median(step_ms)}, {"max", max_ms}};
  json warnings = json::array();
  for (const Warning& w : data.warnings.entries())
    warnings.push_back({{"step", w.step}, {"message", w.message}});
  s["warnings"] = warnings;
  s["warnings_total"] = data.warnings.count();
  s["nan"] = data.lost;
  json probe_json = json::object();
  for (std::size_t p = 0; p < compiled.probes.size(); ++p)
    probe_json[compiled.probes[p].name] = probes.samples.size() > p ? json(probes.samples[p])
                                                                   : json::array();
  s["probes"] = probe_json;
  s["intersections_max"] = probes.intersections_max;
  s["contacts_max"] = probes.contacts_max;
  s["patches_max"] = probes.patches_max;
  s["vr_max"] = probes.vr_max;
  return s;
}

/// Writes `text` to `path` through a temporary file, so a reader never sees half a file.
void write_file_atomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error("cannot write " + tmp.string());
    f << text;
  }
  fs::rename(tmp, path);
}

}  // namespace

int validate_scene(const std::string& scene, const std::vector<std::string>& overrides) {
  scene::SceneSpec spec;
  scene::CompiledScene compiled;
  if (!load_and_compile(scene, overrides, nullptr, spec, compiled)) return 1;
  std::printf("%s: ok (%zu cloth(s), %zu obstacle(s), %zu probe(s))\n", scene.c_str(),
              spec.cloths.size(), spec.obstacles.size(), spec.probes.size());
  return 0;
}

int run_scene(const RunOptions& options) {
  scene::SceneSpec spec;
  scene::CompiledScene compiled;
  if (!load_and_compile(options.scene, options.overrides, &options, spec, compiled)) return 1;
  coupling::set_threads(compiled.model, options.threads);

  // Output folder: created only once the input is known to be good.
  const fs::path out(options.out_dir);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    std::fprintf(stderr, "dexcloth: --out %s: cannot create folder: %s\n", options.out_dir.c_str(),
                 ec.message().c_str());
    return 1;
  }

  coupling::WorldData& data = compiled.data;
  const long total_steps = std::lround(spec.duration / spec.dt);
  const long steps_per_frame = std::max(1L, std::lround(1.0 / (spec.frame_rate * spec.dt)));
  ProgressBar progress(total_steps, spec.dt, !options.quiet && stderr_is_terminal());
  std::vector<double> step_ms;
  step_ms.reserve(static_cast<std::size_t>(total_steps));
  FrameLog frames;

  Recorder recorder(out, spec, compiled, options.export_obj);

  // Simulation loop: record frame 0, then every steps_per_frame steps.
  record_frame(compiled, data, frames);
  recorder.write(compiled);
  while (data.step < total_steps && !data.lost) {
    coupling::step(compiled.model, data);
    step_ms.push_back(data.last_step_ms);
    frames.contacts_max = std::max(frames.contacts_max, data.stats.contacts);
    frames.patches_max = std::max(frames.patches_max, data.stats.patches);
    frames.vr_max = std::max(frames.vr_max, data.stats.vr);
    if (data.step % steps_per_frame == 0 && !data.lost) {
      record_frame(compiled, data, frames);
      recorder.write(compiled);
    }
    progress.update(data.step, data.last_step_ms);
  }
  progress.finish();
  recorder.close();

  write_file_atomically(out / "summary.json",
                        make_summary(spec, compiled, step_ms, frames).dump(2) + "\n");
  if (data.lost) {
    std::fprintf(stderr, "dexcloth: %s: simulation lost its state (NaN) at step %ld, t = %.4f s; "
                 "see %s\n", options.scene.c_str(), data.step, data.time,
                 (out / "summary.json").c_str());
    return 2;
  }
  if (!options.quiet)
    std::printf("dexcloth: %s: %ld steps, median %.2f ms/step; output in %s\n",
                options.scene.c_str(), data.step, median(step_ms), fs::absolute(out).c_str());
  return 0;
}

}  // namespace dexcloth::app
