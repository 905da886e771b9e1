#include "EglBackend.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>

namespace pbf {
namespace {

std::string eglErrorText(const char* what) {
  std::ostringstream text;
  text << "EGL backend: " << what << " failed (EGL error 0x" << std::hex << eglGetError()
       << ")";
  return text.str();
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t length = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += length) {
    const bool starts = p == list || p[-1] == ' ';
    const bool ends = p[length] == ' ' || p[length] == '\0';
    if (starts && ends) return true;
  }
  return false;
}

}  // namespace

struct EglBackend::State {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

EglBackend::EglBackend() : state_(std::make_unique<State>()) {
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasExtension(client_extensions, "EGL_MESA_platform_surfaceless"))
    throw std::runtime_error(
        "EGL backend: EGL_MESA_platform_surfaceless is not available (client extensions: " +
        std::string(client_extensions ? client_extensions : "none") + ")");
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display)
    throw std::runtime_error("EGL backend: eglGetPlatformDisplayEXT is not available");

  state_->display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                         nullptr);
  if (state_->display == EGL_NO_DISPLAY)
    throw std::runtime_error(eglErrorText("eglGetPlatformDisplayEXT(surfaceless)"));
  EGLint major = 0, minor = 0;
  if (!eglInitialize(state_->display, &major, &minor))
    throw std::runtime_error(eglErrorText("eglInitialize"));

  const char* display_extensions = eglQueryString(state_->display, EGL_EXTENSIONS);
  if (!hasExtension(display_extensions, "EGL_KHR_surfaceless_context"))
    throw std::runtime_error("EGL backend: EGL_KHR_surfaceless_context is not available");
  if (!eglBindAPI(EGL_OPENGL_API)) throw std::runtime_error(eglErrorText("eglBindAPI(OpenGL)"));

  // Any config able to render desktop GL; with no surface its buffers never matter.
  const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint config_count = 0;
  if (!eglChooseConfig(state_->display, config_attributes, &config, 1, &config_count) ||
      config_count == 0) {
    if (!hasExtension(display_extensions, "EGL_KHR_no_config_context"))
      throw std::runtime_error(eglErrorText("eglChooseConfig(EGL_OPENGL_BIT)"));
    config = EGL_NO_CONFIG_KHR;
  }

  const int versions[][2] = {{4, 5}, {3, 3}};
  for (const auto& v : versions) {
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, v[0],
                                         EGL_CONTEXT_MINOR_VERSION, v[1],
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_NONE};
    state_->context =
        eglCreateContext(state_->display, config, EGL_NO_CONTEXT, context_attributes);
    if (state_->context != EGL_NO_CONTEXT) break;
  }
  if (state_->context == EGL_NO_CONTEXT)
    throw std::runtime_error(eglErrorText("eglCreateContext(OpenGL 3.3 core)"));
  makeCurrent();
}

EglBackend::~EglBackend() {
  if (state_->display != EGL_NO_DISPLAY) {
    if (eglGetCurrentContext() == state_->context)
      eglMakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (state_->context != EGL_NO_CONTEXT) eglDestroyContext(state_->display, state_->context);
    // No eglTerminate: the surfaceless display is one per process, and terminating it
    // would pull it from under any other renderer still using it.
  }
}

void EglBackend::makeCurrent() {
  if (eglGetCurrentContext() == state_->context) return;
  if (!eglMakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, state_->context))
    throw std::runtime_error(eglErrorText("eglMakeCurrent(surfaceless)"));
}

GlBackend::Proc EglBackend::getProcAddress(const char* name) const {
  return reinterpret_cast<Proc>(eglGetProcAddress(name));
}

}  // namespace pbf
