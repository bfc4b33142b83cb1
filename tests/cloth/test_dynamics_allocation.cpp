// After the first step, a dynamics step allocates nothing (STYLE.md: the inner loop does not
// allocate). glibc's malloc family is interposed to count heap allocations in this binary.
#include <gtest/gtest.h>

#include <cstdlib>
#include <utility>
#include <vector>

#include "cloth/dynamics.hpp"
#include "cloth/mesh.hpp"
#include "cloth/model.hpp"

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
}

namespace {
long g_allocations = 0;
}  // namespace

extern "C" {
void* malloc(std::size_t n) {
  ++g_allocations;
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t size) {
  ++g_allocations;
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t n) {
  ++g_allocations;
  return __libc_realloc(p, n);
}
}

using namespace dexcloth;
using namespace dexcloth::cloth;

TEST(DynamicsAllocation, StepsAfterTheFirstDoNotAllocate) {
  // 12×12 runs single-threaded; 40×40 with two threads takes the parallel (OpenMP) PCG path.
  for (const auto& [solver, n] : {std::pair{LinearSolver::cholesky, 12}, std::pair{LinearSolver::pcg, 12},
                                  std::pair{LinearSolver::pcg, 40}}) {
    const ClothMesh mesh = make_grid(0.3, 0.3, n, n);
    ClothModel model = build_model(mesh, Material{});
    model.solver.linear_solver = solver;
    model.solver.threads = 2;
    ClothState state = make_state(model, mesh.x);
    const std::vector<VelocityConstraint> handles = {{0, Vec3::Zero()}, {n - 1, Vec3(0, 0, 0.05)}};
    ASSERT_TRUE(step_dynamics(model, state, 0.005, Vec3(0, 0, -9.81), handles).ok);
    const long before = g_allocations;
    bool ok = true;
    for (int n = 0; n < 10; ++n)
      ok = step_dynamics(model, state, 0.005, Vec3(0, 0, -9.81), handles).ok && ok;
    const long allocations = g_allocations - before;
    EXPECT_TRUE(ok);
    EXPECT_EQ(allocations, 0) << "solver " << static_cast<int>(solver) << ", " << n << "×" << n;
    // The counter works: building a model allocates.
    const long probe = g_allocations;
    const ClothModel other = build_model(mesh, Material{});
    EXPECT_GT(g_allocations, probe);
  }
}
