/// dexcloth command-line interface: run | validate | view | snapshot.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "core/heap.hpp"
#include "io/obj_export.hpp"
#include "io/recording.hpp"
#include "io/viewer_launch.hpp"
#include "run_command.hpp"

namespace {

/// A run's output folder holds its recording in recording/; a recording folder is taken as is.
std::string recording_dir(const std::string& dir) {
  const std::filesystem::path nested = std::filesystem::path(dir) / "recording";
  return std::filesystem::exists(nested / "recording.json") ? nested.string() : dir;
}

}  // namespace

int main(int argc, char** argv) {
  dexcloth::keep_heap_top();
  CLI::App cli{"dexcloth: hands and grippers manipulating cloth (Bai & Liu coupling on DART)"};
  cli.require_subcommand(1);

  // dexcloth run
  dexcloth::app::RunOptions run;
  CLI::App* run_cmd =
      cli.add_subcommand("run", "Run a scene and write summary.json and a recording");
  run_cmd->add_option("scene", run.scene, "Scene file (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  run_cmd->add_option("--out", run.out_dir, "Output folder")->required();
  run_cmd->add_option("--duration", run.duration, "Simulated time [s] (default: the scene's)")
      ->check(CLI::PositiveNumber);
  run_cmd->add_option("--coupling", run.coupling, "Coupling mode (default: the scene's)")
      ->check(CLI::IsMember({"bai-liu", "kinematic"}));
  run_cmd->add_option("--set", run.overrides,
                      "Override a scene value: /json/pointer=value (repeatable)");
  run.threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 2u));
  run_cmd
      ->add_option("--threads", run.threads,
                   "Threads of the step's parallel parts (default: 2, or 1 on one core); the "
                   "results do not depend on it")
      ->check(CLI::Range(1, 64));
  run_cmd->add_flag("--quiet", run.quiet, "No progress bar, no closing line");
  run_cmd->add_flag("--export-obj", run.export_obj, "Also write one OBJ per cloth per frame");

  // dexcloth validate
  std::string validate_scene;
  std::vector<std::string> validate_overrides;
  CLI::App* validate_cmd =
      cli.add_subcommand("validate", "Check a scene; print every problem; exit 0 or 1");
  validate_cmd->add_option("scene", validate_scene, "Scene file (JSON)")
      ->required()
      ->check(CLI::ExistingFile);
  validate_cmd->add_option("--set", validate_overrides,
                           "Override a scene value: /json/pointer=value (repeatable)");

  // dexcloth view
  std::string view_dir;
  int view_port = 8080;
  CLI::App* view_cmd =
      cli.add_subcommand("view", "Serve a run's recording and the web viewer on 127.0.0.1");
  view_cmd->add_option("dir", view_dir, "Run output folder (or its recording/ folder)")->required();
  view_cmd->add_option("--port", view_port, "Port (0 picks a free one)")
      ->check(CLI::Range(0, 65535));

  // dexcloth snapshot
  std::string snap_dir, snap_png, snap_mp4;
  std::vector<int> snap_frames;
  CLI::App* snap_cmd =
      cli.add_subcommand("snapshot", "Render frames headless (chromium) to PNG or MP4");
  snap_cmd->add_option("dir", snap_dir, "Run output folder (or its recording/ folder)")->required();
  snap_cmd->add_option("--frames", snap_frames, "Frame indices, e.g. 0,50,100")->delimiter(',');
  snap_cmd->add_option("--png", snap_png, "Folder for one PNG per frame (needs --frames)");
  snap_cmd->add_option("--mp4", snap_mp4, "MP4 file of the frames (all frames without --frames)");

  // dexcloth export
  std::string export_dir, export_obj;
  std::vector<long> export_frames;
  CLI::App* export_cmd = cli.add_subcommand("export", "Write a recording as an OBJ sequence");
  export_cmd->add_option("dir", export_dir, "Run output folder (or its recording/ folder)")
      ->required();
  export_cmd->add_option("--obj", export_obj, "Output folder for the OBJ files")->required();
  export_cmd->add_option("--frames", export_frames, "Frame indices (default: all)")->delimiter(',');

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  try {
    if (*run_cmd) return dexcloth::app::run_scene(run);
    if (*validate_cmd) return dexcloth::app::validate_scene(validate_scene, validate_overrides);
    if (*view_cmd) return dexcloth::io::run_viewer_server(recording_dir(view_dir), view_port);
    if (*snap_cmd) {
      if (snap_png.empty() && snap_mp4.empty()) {
        std::fprintf(stderr,
                     "dexcloth snapshot: give --png OUTDIR (with --frames) or --mp4 FILE\n");
        return 1;
      }
      return dexcloth::io::run_snapshot(recording_dir(snap_dir), snap_frames, snap_png, snap_mp4);
    }
    if (*export_cmd) {
      dexcloth::io::RecordingReader reader;
      reader.open(recording_dir(export_dir));
      const long files = dexcloth::io::export_obj_sequence(reader, export_obj, export_frames);
      std::printf("dexcloth: wrote %ld OBJ files to %s\n", files, export_obj.c_str());
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dexcloth: %s\n", e.what());
    return 2;
  }
  return 1;
}
