// The interface of the OpenImageIO module (oiio_module.cpp, libvoxgi_oiio.so), which
// image.cpp loads with dlopen on first use. Each function returns 0 on success, or
// non-zero with a one-line message in err (errLen bytes, NUL-terminated).
#ifndef VOXGI_IMAGE_OIIO_MODULE_H
#define VOXGI_IMAGE_OIIO_MODULE_H

extern "C" {

// Returns room for width x height x channels floats (owned by the caller's
// context), or null.
typedef float* (*VoxgiOiioAllocate)(void* context, int width, int height, int channels);

// Writes RGBA rows (top-left origin; 8-bit sRGB, or isFloat: linear float) as RGB
// into `tmp`, in the format `path`'s extension names.
int voxgiOiioWrite(const char* path, const char* tmp, int width, int height, int isFloat,
                   const void* rgba, char* err, int errLen);
typedef int (*VoxgiOiioWriteFn)(const char*, const char*, int, int, int, const void*, char*, int);

// Reads the image at path as stored (8-bit files map to [0, 1]).
int voxgiOiioRead(const char* path, VoxgiOiioAllocate allocate, void* context, char* err,
                  int errLen);
typedef int (*VoxgiOiioReadFn)(const char*, VoxgiOiioAllocate, void*, char*, int);
}

#endif  // VOXGI_IMAGE_OIIO_MODULE_H
