#include "app/environment.h"

#include <cstdint>
#include <cstdlib>

namespace voxgi::app {
namespace {

int eglDevice() {
  const char* env = std::getenv("VOXGI_EGL_DEVICE");
  return env ? std::atoi(env) : -1;
}

uint64_t voxelBudgetBytes() {
  const char* env = std::getenv("VOXGI_VOXEL_BUDGET_MB");
  if (!env) return 0;
  const long long mb = std::atoll(env);
  return mb > 0 ? static_cast<uint64_t>(mb) << 20 : 0;
}

}  // namespace

void applyEnvironment(Invocation* inv) {
  const int device = eglDevice();
  const uint64_t budget = voxelBudgetBytes();
  for (RenderOptions* o : {&inv->render, &inv->bench.render}) {
    o->eglDevice = device;
    o->render.voxelBudgetBytes = budget;
  }
  inv->view.render.voxelBudgetBytes = budget;
}

}  // namespace voxgi::app
