// The environment variables that set what the layers below app/ are handed as
// settings (the libraries read none):
//   VOXGI_EGL_DEVICE=N       EGL device N of the enumeration (gl::ContextOptions::eglDevice)
//   VOXGI_VOXEL_BUDGET_MB=M  the voxel grid's memory budget, M MiB
//                            (render::RenderSettings::voxelBudgetBytes)
#ifndef VOXGI_APP_ENVIRONMENT_H
#define VOXGI_APP_ENVIRONMENT_H

#include "app/cli.h"

namespace voxgi::app {

// Sets, in every command's options of `inv`, what the environment asks for; leaves
// the defaults where a variable is unset or not a valid value.
void applyEnvironment(Invocation* inv);

}  // namespace voxgi::app

#endif  // VOXGI_APP_ENVIRONMENT_H
