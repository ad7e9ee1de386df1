// The one GL header our code includes: the glad 4.5 core loader, fed by the
// current context backend's get-proc-address, so calls never resolve by link order
// to another library's GL entry points (libOSMesa and libOpenGL both export them).
#ifndef VOXGI_GL_GL_H
#define VOXGI_GL_GL_H

#include <glad/gl.h>

#endif  // VOXGI_GL_GL_H
