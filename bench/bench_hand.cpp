/// Cost of one world step with the 33-DOF hand (DART 6.12: Bullet detector, LCP contacts, stable
/// joint PDs), stepped by coupling::step exactly as `dexcloth run` steps a scene without cloth:
///   BM_HandAlone       the hand free in the air, wrist and joint PDs holding the 'pinch' pose
///                      (no contacts), after kSettle s of settling;
///   BM_HandGrasp/box   scenes/hand_grasp_box.json from kHeld s on: the box lifted and held;
///   BM_HandGrasp/ball  scenes/hand_grasp_ball.json from kHeld s on: the ball lifted and held.
/// Steps past a scene's duration keep its last keyframes, so the grasp stays held while timed.
/// Counters (means over the timed steps): contacts, every contact point DART reports per step;
/// object_contacts, the hand's contact points on the grasped object. Run (Release):
///   build/bench/bench_hand
#include <benchmark/benchmark.h>

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "coupling/step.hpp"
#include "scene/compile.hpp"
#include "scene/load.hpp"

namespace {

using namespace dexcloth;

const std::string kScenes = std::string(DEXCLOTH_SOURCE_DIR) + "/scenes";
constexpr double kSettle = 0.5;  // hand alone: settling time before timing [s]
constexpr double kHeld = 1.7;    // grasp scenes: the object is lifted and held from here [s]

/// Steps `scene` until its time reaches t [s].
void advance_to(scene::CompiledScene& scene, double t) {
  while (scene.data.time < t - 1e-9 && !scene.data.lost) coupling::step(scene.model, scene.data);
}

/// The hand of the grasp scenes alone, 0.5 m above nothing, holding the 'pinch' pose.
scene::CompiledScene hand_alone() {
  const nlohmann::json doc = {
      {"name", "hand_alone"},
      {"cloths", nlohmann::json::array()},
      {"bodies",
       {{{"name", "hand"},
         {"urdf", "../assets/hands/human_hand.urdf"},
         {"poses", "../assets/hands/human_hand.poses.json"},
         {"root", {{"translation", {0.0, 0.0, 0.5}}}},
         {"controller",
          {{"gravity_compensation", "full"},
           {"joint_pd", {{"kp", 2.0}, {"kd", 0.02}, {"keyframes", {{{"t", 0.0}, {"pose", "pinch"}}}}}},
           {"wrist", nlohmann::json::object()}}}}}}};
  return scene::compile_scene(scene::parse_scene(doc, kScenes + "/hand_alone.json", kScenes));
}

/// Times single steps of `scene`; counts contacts, and the hand's contacts on `object` if given.
void time_steps(benchmark::State& bench, scene::CompiledScene& scene, const std::string& object) {
  const rigid::RigidWorld& world = *scene.data.rigid.world;
  const rigid::SkeletonId hand = world.skeleton("hand");
  const std::optional<rigid::BodyId> body = object.empty() ? std::nullopt : world.find_body(object);
  const double z_held = body ? world.com_W(*body).z() : 0.0;
  double contacts = 0.0;
  double object_contacts = 0.0;
  for (auto _ : bench) {
    coupling::step(scene.model, scene.data);
    contacts += world.num_contacts();
    if (body) {
      for (const rigid::ContactPoint& c : world.contacts(*body))
        object_contacts += world.body_skeleton(c.other) == hand ? 1.0 : 0.0;
    }
  }
  if (scene.data.lost) bench.SkipWithError("state lost (NaN)");
  if (body && world.com_W(*body).z() < z_held - 0.01) bench.SkipWithError("the object slipped");
  const double n = static_cast<double>(bench.iterations());
  bench.counters["contacts"] = contacts / n;
  if (body) bench.counters["object_contacts"] = object_contacts / n;
}

void BM_HandAlone(benchmark::State& bench) {
  scene::CompiledScene scene = hand_alone();
  advance_to(scene, kSettle);
  time_steps(bench, scene, "");
}

void BM_HandGrasp(benchmark::State& bench, const std::string& file, const std::string& object) {
  scene::CompiledScene scene = scene::compile_scene(scene::load_scene(kScenes + "/" + file));
  advance_to(scene, kHeld);
  time_steps(bench, scene, object);
}

}  // namespace

BENCHMARK(BM_HandAlone)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_HandGrasp, box, std::string("hand_grasp_box.json"), std::string("box/body"))
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_HandGrasp, ball, std::string("hand_grasp_ball.json"), std::string("ball/body"))
    ->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
