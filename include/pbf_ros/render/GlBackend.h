#pragma once
// A headless OpenGL context: where GL comes from, and nothing else.
//
// Two implementations, chosen by name at run time:
//  - "osmesa": Mesa's off-screen library (core profile through OSMesaCreateContextAttribs).
//    The default, because it needs no display, no device and no EGL platform support.
//  - "egl": EGL on the surfaceless Mesa platform (EGL_MESA_platform_surfaceless), for Mesa
//    versions that no longer ship OSMesa (gone from Mesa 25.1).
// Every GL entry point the renderer uses is looked up through getProcAddress(): the
// library never links libGL/libOpenGL, whose symbols would shadow OSMesa's and silently
// send every call to a dispatch table with no context.
//
// A context belongs to one thread at a time: create it, make it current and use it on the
// thread that renders (see FluidRenderer).

#include <memory>
#include <string>
#include <vector>

namespace pbf {

class GlBackend {
 public:
  using Proc = void (*)();

  virtual ~GlBackend() = default;

  // Binds the context to the calling thread. Throws std::runtime_error on failure.
  virtual void makeCurrent() = 0;

  // Address of a GL function of this context, or nullptr if it has none by that name.
  virtual Proc getProcAddress(const char* name) const = 0;

  // "osmesa" or "egl".
  virtual std::string name() const = 0;
};

// Creates and makes current a core-profile context (OpenGL >= 3.3) of the named kind:
// "osmesa" or "egl". Throws std::invalid_argument for any other name and
// std::runtime_error (saying which call failed) when the platform cannot provide it.
std::unique_ptr<GlBackend> createGlBackend(const std::string& kind);

// The names createGlBackend accepts.
std::vector<std::string> glBackendNames();

}  // namespace pbf
