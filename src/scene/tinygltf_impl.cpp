// tinygltf's implementation, for builds that compile it themselves (VOXGI_FUZZ);
// other builds link Debian's libtinygltf. stb_image comes from libstb either way.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
