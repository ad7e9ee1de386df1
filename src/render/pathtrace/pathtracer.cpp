#include "render/pathtrace/pathtracer.h"

#include "core/log.h"

namespace voxgi::render {

PathtraceDevice parsePathtraceDevice(const std::string& name) {
  if (name == "auto") return PathtraceDevice::kAuto;
  if (name == "cpu") return PathtraceDevice::kCpu;
  if (name == "gl") return PathtraceDevice::kGl;
  throw Error(strf("unknown path tracer device '%s' (auto, cpu, gl)", name.c_str()));
}

const char* pathtraceDeviceName(PathtraceDevice device) {
  switch (device) {
    case PathtraceDevice::kAuto:
      return "auto";
    case PathtraceDevice::kCpu:
      return "cpu";
    case PathtraceDevice::kGl:
      return "gl";
  }
  return "?";
}

bool isSoftwareRenderer(const std::string& glRenderer) {
  for (const char* software : {"llvmpipe", "softpipe", "swrast"})
    if (glRenderer.find(software) != std::string::npos) return true;
  return false;
}

PathtraceDevice resolvePathtraceDevice(PathtraceDevice device, const std::string& glRenderer) {
  if (device != PathtraceDevice::kAuto) return device;
  return isSoftwareRenderer(glRenderer) ? PathtraceDevice::kCpu : PathtraceDevice::kGl;
}

}  // namespace voxgi::render
