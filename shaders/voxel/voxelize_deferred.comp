#version 450 core
// Voxelization, the fragments the raster and the compute path deferred: those
// whose voxel another thread was still claiming when the wait for its slot ran out
// (voxel_fragment.glsl, voxel_shared.h). One invocation per record, in two
// dispatches. The first claims each record's voxel where no one has (a wait cut
// short here only means another invocation of this dispatch is claiming it, and
// publishes before the dispatch ends); the second, with every claim published, adds
// each record to its voxel's sums, as the fragment would have.
#include "voxel_shared.h"

layout(local_size_x = kResolveGroupSize) in;

layout(std140, binding = kVoxelParamsBinding) uniform VoxelBlock { VoxelParams voxel; };

#include "voxel_fragment.glsl"

layout(location = kVoxelDeferredAddLocation) uniform uint addPass;

void main() {
  uint i = (gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x) * kResolveGroupSize +
           gl_LocalInvocationIndex;
  if (i >= min(stats.deferred, voxel.limits.w)) return;
  VoxelDeferred d = deferred[i];
  uint code = d.voxel.x;
  ivec3 p = ivec3(code & 1023u, (code >> 10) & 1023u, code >> 20);
  uint slot = voxelSlot(p);
  if (addPass == 0u || slot == kSlotFull) return;
  if (slot == kSlotPending) {
    atomicAdd(stats.deferredLost, 1u);  // never expected: the pass runs again
    return;
  }
  voxelAddToSlot(slot, d.voxel.y, uvec3(d.voxel.zw, d.albedoN.x), d.albedoN.yzw, d.emission.xyz,
                 uvec2(d.emission.w & 0xFFFFu, d.emission.w >> 16));
}
