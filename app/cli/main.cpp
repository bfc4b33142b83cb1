/// dexcloth command-line interface: run | validate | view | snapshot.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "run_command.hpp"

int main(int argc, char** argv) {
  CLI::App cli{"dexcloth: hands and grippers manipulating cloth (Bai & Liu coupling on DART)"};
  cli.require_subcommand(1);

  // dexcloth run
  dexcloth::app::RunOptions run;
  CLI::App* run_cmd = cli.add_subcommand("run", "Run a scene and write summary.json and a recording");
  run_cmd->add_option("scene", run.scene, "Scene file (JSON)")->required()->check(CLI::ExistingFile);
  run_cmd->add_option("--out", run.out_dir, "Output folder")->required();
  run_cmd->add_option("--duration", run.duration, "Simulated time [s] (default: the scene's)")
      ->check(CLI::PositiveNumber);
  run_cmd->add_option("--coupling", run.coupling, "Coupling mode (default: the scene's)")
      ->check(CLI::IsMember({"bai-liu", "kinematic"}));
  run_cmd->add_option("--set", run.overrides,
                      "Override a scene value: /json/pointer=value (repeatable)");
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

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  try {
    if (*run_cmd) return dexcloth::app::run_scene(run);
    if (*validate_cmd) return dexcloth::app::validate_scene(validate_scene, validate_overrides);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dexcloth: %s\n", e.what());
    return 2;
  }
  return 1;
}
