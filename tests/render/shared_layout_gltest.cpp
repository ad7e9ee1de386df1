// The std430/std140 layouts that GLSL gives the structs of every *_shared.h that
// the host uploads or reads back (octree, rtgi, voxel, scene and pathtrace) agree
// with the C++ side of the same headers: every member's offset, and the struct's
// size (the array stride, or the block's size where the struct fills a block).
// GpuBvhNode and GpuPtTriangle are read as buffer textures of 16-byte texels, not
// as GLSL structs: their C++ layout is asserted in pathtrace_shared.h.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "gl/program_cache.h"
#include "octree_shared.h"
#include "pathtrace_shared.h"
#include "rtgi_shared.h"
#include "scene_shared.h"
#include "support/gl_fixture.h"
#include "support/test_paths.h"
#include "voxel_shared.h"

namespace voxgi::test {
namespace {

struct Member {
  std::string name;  // as GL names it: "instance.member", "array[0].member"
  size_t offset;     // offsetof on the C++ side
};

#define VOXGI_MEMBER(prefix, type, member, suffix)                   \
  Member {                                                           \
    std::string(prefix) + #member + (suffix), offsetof(type, member) \
  }

class SharedLayoutTest : public GlTest {
 protected:
  GLint query(GLuint program, GLenum iface, const std::string& name, GLenum prop) {
    const GLuint index = glGetProgramResourceIndex(program, iface, name.c_str());
    EXPECT_NE(index, GL_INVALID_INDEX) << name;
    if (index == GL_INVALID_INDEX) return -1;
    GLint v = -1;
    glGetProgramResourceiv(program, iface, index, 1, &prop, 1, nullptr, &v);
    return v;
  }
  // Offsets of members of a struct that is an SSBO's or a uniform block's first
  // member (so its offsets are the block's).
  void expectOffsets(GLuint program, GLenum iface, const std::vector<Member>& members) {
    for (const Member& m : members)
      EXPECT_EQ(query(program, iface, m.name, GL_OFFSET), static_cast<GLint>(m.offset)) << m.name;
  }
  GLuint program(const std::string& shader) { return cache_.get({{shader}, {}}).id(); }

  gl::ProgramCache cache_{sourceDir() + "/shaders"};
};

TEST_F(SharedLayoutTest, OctreeParamsMatchCpp) {
  using gpu::OctreeParams;
  const GLuint p = program("voxel/octree_raycast.comp");
  expectOffsets(p, GL_UNIFORM,
                {VOXGI_MEMBER("octree.", OctreeParams, origin, ""),
                 VOXGI_MEMBER("octree.", OctreeParams, info, ""),
                 VOXGI_MEMBER("octree.", OctreeParams, pass, ""),
                 VOXGI_MEMBER("octree.", OctreeParams, light, ""),
                 VOXGI_MEMBER("octree.", OctreeParams, slice, ""),
                 VOXGI_MEMBER("octree.", OctreeParams, blend, ""),
                 VOXGI_MEMBER("octree.", OctreeParams, sides, ""),
                 VOXGI_MEMBER("octree.", OctreeParams, rays, "")});
  EXPECT_EQ(query(p, GL_UNIFORM_BLOCK, "OctreeBlock", GL_BUFFER_DATA_SIZE),
            static_cast<GLint>(sizeof(OctreeParams)));
}

TEST_F(SharedLayoutTest, OctreeRayMatchesCpp) {
  using gpu::OctreeRay;
  const GLuint p = program("voxel/octree_raycast.comp");
  expectOffsets(p, GL_BUFFER_VARIABLE,
                {VOXGI_MEMBER("rays[0].", OctreeRay, origin, ""),
                 VOXGI_MEMBER("rays[0].", OctreeRay, direction, ""),
                 VOXGI_MEMBER("rays[0].", OctreeRay, invDirection, "")});
  EXPECT_EQ(query(p, GL_BUFFER_VARIABLE, "rays[0].origin", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(OctreeRay)));
}

TEST_F(SharedLayoutTest, OctreeCountersMatchCpp) {
  using gpu::OctreeCounters;
  const GLuint p = program("voxel/octree_build.comp");
  expectOffsets(p, GL_BUFFER_VARIABLE,
                {VOXGI_MEMBER("counters.", OctreeCounters, nodeCount, ""),
                 VOXGI_MEMBER("counters.", OctreeCounters, overflow, ""),
                 VOXGI_MEMBER("counters.", OctreeCounters, twoSided, ""),
                 VOXGI_MEMBER("counters.", OctreeCounters, pad1, ""),
                 VOXGI_MEMBER("counters.", OctreeCounters, levelStart, "[0]")});
  EXPECT_EQ(query(p, GL_SHADER_STORAGE_BLOCK, "Counters", GL_BUFFER_DATA_SIZE),
            static_cast<GLint>(sizeof(OctreeCounters)));
}

TEST_F(SharedLayoutTest, RtgiParamsMatchCpp) {
  using gpu::RtgiParams;
  const GLuint p = program("render/rtgi/rtgi_mask.comp");
  expectOffsets(p, GL_UNIFORM,
                {VOXGI_MEMBER("rtgi.", RtgiParams, frameIndex, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, seed, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, width, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, height, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, lightCount, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, emitterCount, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, flags, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, camera, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, cameraRight, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, cameraUp, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, cameraForward, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, interleave, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, selectLevel, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, selectKind, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, workFlags, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, previousViewProj, "[0]"),
                 VOXGI_MEMBER("rtgi.", RtgiParams, historyCap, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, glossyHistory, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, mirrorHistory, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, edgeHistory, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, denoiseLuminance, ""),
                 VOXGI_MEMBER("rtgi.", RtgiParams, denoisePlane, "")});
  EXPECT_EQ(query(p, GL_UNIFORM, "rtgi.previousViewProj[0]", GL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(gpu::vec4)));
  EXPECT_EQ(query(p, GL_UNIFORM_BLOCK, "RtgiBlock", GL_BUFFER_DATA_SIZE),
            static_cast<GLint>(sizeof(RtgiParams)));
}

TEST_F(SharedLayoutTest, PixelListHeaderMatchesCpp) {
  using gpu::PixelListHeader;
  const GLuint p = program("render/rtgi/rtgi_select.comp");
  expectOffsets(p, GL_BUFFER_VARIABLE,
                {VOXGI_MEMBER("header.", PixelListHeader, groups, ""),
                 VOXGI_MEMBER("header.", PixelListHeader, count, ""),
                 {"pixels[0]", sizeof(PixelListHeader)}});
}

TEST_F(SharedLayoutTest, VoxelParamsMatchCpp) {
  using gpu::VoxelParams;
  const GLuint p = program("voxel/resolve.comp");
  expectOffsets(p, GL_UNIFORM,
                {VOXGI_MEMBER("voxel.", VoxelParams, gridOrigin, ""),
                 VOXGI_MEMBER("voxel.", VoxelParams, gridInfo, ""),
                 VOXGI_MEMBER("voxel.", VoxelParams, slotInfo, ""),
                 VOXGI_MEMBER("voxel.", VoxelParams, samplePositions, "[0]"),
                 VOXGI_MEMBER("voxel.", VoxelParams, limits, "")});
  EXPECT_EQ(query(p, GL_UNIFORM, "voxel.samplePositions[0]", GL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(gpu::vec4)));
  EXPECT_EQ(query(p, GL_UNIFORM_BLOCK, "VoxelBlock", GL_BUFFER_DATA_SIZE),
            static_cast<GLint>(sizeof(VoxelParams)));
}

TEST_F(SharedLayoutTest, VoxelStatsMatchCpp) {
  using gpu::VoxelStats;
  const GLuint p = program("voxel/resolve.comp");
  expectOffsets(p, GL_BUFFER_VARIABLE,
                {VOXGI_MEMBER("stats.", VoxelStats, listCount, ""),
                 VOXGI_MEMBER("stats.", VoxelStats, pad0, "[0]"),
                 VOXGI_MEMBER("stats.", VoxelStats, brickCount, ""),
                 VOXGI_MEMBER("stats.", VoxelStats, pad1, "[0]"),
                 VOXGI_MEMBER("stats.", VoxelStats, checksumSum, ""),
                 VOXGI_MEMBER("stats.", VoxelStats, checksumXor, ""),
                 VOXGI_MEMBER("stats.", VoxelStats, smallTriangles, ""),
                 VOXGI_MEMBER("stats.", VoxelStats, pad2, "[0]"),
                 VOXGI_MEMBER("stats.", VoxelStats, deferred, ""),
                 VOXGI_MEMBER("stats.", VoxelStats, deferredLost, ""),
                 VOXGI_MEMBER("stats.", VoxelStats, pad3, "[0]")});
  EXPECT_EQ(query(p, GL_SHADER_STORAGE_BLOCK, "Stats", GL_BUFFER_DATA_SIZE),
            static_cast<GLint>(sizeof(VoxelStats)));
}

TEST_F(SharedLayoutTest, VoxelDeferredMatchesCpp) {
  using gpu::VoxelDeferred;
  const GLuint p = program("voxel/voxelize_deferred.comp");
  expectOffsets(p, GL_BUFFER_VARIABLE,
                {VOXGI_MEMBER("deferred[0].", VoxelDeferred, voxel, ""),
                 VOXGI_MEMBER("deferred[0].", VoxelDeferred, albedoN, ""),
                 VOXGI_MEMBER("deferred[0].", VoxelDeferred, emission, "")});
  EXPECT_EQ(query(p, GL_BUFFER_VARIABLE, "deferred[0].voxel", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(VoxelDeferred)));
}

TEST_F(SharedLayoutTest, SceneStructsMatchCpp) {
  using gpu::GpuEmitter;
  using gpu::GpuFrame;
  using gpu::GpuLight;
  using gpu::GpuMaterial;
  const GLuint p = cache_.get({{"render/raster.vert", "render/raster.frag"}, {}}).id();
  const GLenum bv = GL_BUFFER_VARIABLE;
  expectOffsets(p, bv,
                {VOXGI_MEMBER("materials[0].", GpuMaterial, baseColor, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, emission, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, normalTexture, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, metallic, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, roughness, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, alphaCutoff, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, normalScale, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, flags, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, texture, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, emissiveTexture, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, metallicRoughnessTexture, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, occlusionStrength, ""),
                 VOXGI_MEMBER("materials[0].", GpuMaterial, occlusionTexture, ""),
                 VOXGI_MEMBER("lights[0].", GpuLight, positionType, ""),
                 VOXGI_MEMBER("lights[0].", GpuLight, directionRange, ""),
                 VOXGI_MEMBER("lights[0].", GpuLight, radiance, ""),
                 VOXGI_MEMBER("lights[0].", GpuLight, cone, ""),
                 VOXGI_MEMBER("emitters[0].", GpuEmitter, a, ""),
                 VOXGI_MEMBER("emitters[0].", GpuEmitter, kind, ""),
                 VOXGI_MEMBER("emitters[0].", GpuEmitter, b, ""),
                 VOXGI_MEMBER("emitters[0].", GpuEmitter, area, ""),
                 VOXGI_MEMBER("emitters[0].", GpuEmitter, c, ""),
                 VOXGI_MEMBER("emitters[0].", GpuEmitter, radiance, ""),
                 VOXGI_MEMBER("emitters[0].", GpuEmitter, twoSided, "")});
  EXPECT_EQ(query(p, bv, "materials[0].baseColor", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(GpuMaterial)));
  EXPECT_EQ(query(p, bv, "lights[0].positionType", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(GpuLight)));
  EXPECT_EQ(query(p, bv, "emitters[0].a", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(GpuEmitter)));
  expectOffsets(p, GL_UNIFORM,
                {VOXGI_MEMBER("frame.", GpuFrame, viewProj, "[0]"),
                 VOXGI_MEMBER("frame.", GpuFrame, cameraPosition, ""),
                 VOXGI_MEMBER("frame.", GpuFrame, counts, "")});
  EXPECT_EQ(query(p, GL_UNIFORM_BLOCK, "FrameBlock", GL_BUFFER_DATA_SIZE),
            static_cast<GLint>(sizeof(GpuFrame)));
}

TEST_F(SharedLayoutTest, PathtraceStructsMatchCpp) {
  using gpu::GpuPtEmissive;
  using gpu::GpuPtParams;
  const GLuint p = program("render/pathtrace.comp");
  const GLenum bv = GL_BUFFER_VARIABLE;
  expectOffsets(p, bv,
                {VOXGI_MEMBER("emissive[0].", GpuPtEmissive, v0, ""),
                 VOXGI_MEMBER("emissive[0].", GpuPtEmissive, e1, ""),
                 VOXGI_MEMBER("emissive[0].", GpuPtEmissive, e2, ""),
                 VOXGI_MEMBER("emissive[0].", GpuPtEmissive, radiance, ""),
                 VOXGI_MEMBER("emissive[0].", GpuPtEmissive, uv01, ""),
                 VOXGI_MEMBER("emissive[0].", GpuPtEmissive, uv2, "")});
  EXPECT_EQ(query(p, bv, "sceneIndices[0]", GL_ARRAY_STRIDE), 4);
  EXPECT_EQ(query(p, bv, "emissive[0].v0", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(GpuPtEmissive)));
  expectOffsets(p, GL_UNIFORM,
                {VOXGI_MEMBER("params.", GpuPtParams, cameraPosition, ""),
                 VOXGI_MEMBER("params.", GpuPtParams, cameraRight, ""),
                 VOXGI_MEMBER("params.", GpuPtParams, cameraUp, ""),
                 VOXGI_MEMBER("params.", GpuPtParams, cameraForward, ""),
                 VOXGI_MEMBER("params.", GpuPtParams, image, ""),
                 VOXGI_MEMBER("params.", GpuPtParams, tile, ""),
                 VOXGI_MEMBER("params.", GpuPtParams, depth, ""),
                 VOXGI_MEMBER("params.", GpuPtParams, reserved, "")});
  EXPECT_EQ(query(p, GL_UNIFORM_BLOCK, "PtParamsBlock", GL_BUFFER_DATA_SIZE),
            static_cast<GLint>(sizeof(GpuPtParams)));
}

#undef VOXGI_MEMBER

}  // namespace
}  // namespace voxgi::test
