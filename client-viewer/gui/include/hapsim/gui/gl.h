// OpenGL 3.3 core entry points, called directly through libGL (glvnd),
// which dispatches to whichever context is current: a GLFW window's (GLX)
// or the headless EGL one. No loader needed.
#pragma once
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/gl.h>
#include <GL/glext.h>
