#include "coupling/step.hpp"

#include <chrono>
#include <string>

namespace dexcloth::coupling {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Hard velocity constraints that carry every handle vertex to its keyframed place at t + h.
void handle_constraints(const ClothBody& body, const cloth::ClothState& state, double t_next,
                        double h, std::vector<cloth::VelocityConstraint>& out) {
  out.clear();
  for (const Handle& handle : body.handles) {
    const Vec3 offset = handle.motion.translation(t_next);
    for (std::size_t k = 0; k < handle.vertices.size(); ++k) {
      const int i = handle.vertices[k];
      const Vec3 target = handle.rest.row(static_cast<Eigen::Index>(k)).transpose() + offset;
      out.push_back({i, (target - state.x.row(i).transpose()) / h});
    }
  }
}

}  // namespace

void step(const WorldModel& model, WorldData& data) {
  const auto start = Clock::now();
  const double h = model.dt;
  std::vector<cloth::VelocityConstraint>& constraints = data.scratch_constraints;

  // Cloth dynamics: implicit Euler with handles as hard constraints.
  for (std::size_t c = 0; c < model.cloths.size(); ++c) {
    const ClothBody& body = model.cloths[c];
    cloth::ClothState& state = data.cloths[c];
    handle_constraints(body, state, data.time + h, h, constraints);
    const cloth::DynamicsReport report =
        cloth::solve_velocities(body.model, state, h, model.gravity, constraints);
    if (!report.ok) data.warnings.add(data.step, body.name + ": " + report.message);
    cloth::advance_positions(state, h);
  }
  data.timings.cloth += seconds_since(start);

  data.time += h;
  ++data.step;
  if (!state_is_finite(data)) {
    data.lost = true;
    data.warnings.add(data.step, "state lost: NaN or infinite cloth position/velocity");
  }
  const double elapsed = seconds_since(start);
  data.timings.total += elapsed;
  data.last_step_ms = 1e3 * elapsed;
}

}  // namespace dexcloth::coupling
