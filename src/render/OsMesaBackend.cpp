#include "OsMesaBackend.h"

#include <GL/osmesa.h>

#include <stdexcept>
#include <vector>

namespace pbf {

struct OsMesaBackend::State {
  OSMesaContext context = nullptr;
  // OSMesa needs a colour buffer to make a context current; everything is drawn into
  // framebuffer objects, so one pixel is enough.
  std::vector<unsigned char> dummy_buffer = std::vector<unsigned char>(4, 0);
};

OsMesaBackend::OsMesaBackend() : state_(std::make_unique<State>()) {
  // Ask for the newest core profile first; 3.3 is all the shaders need.
  const int versions[][2] = {{4, 5}, {3, 3}};
  for (const auto& v : versions) {
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA,
                              OSMESA_DEPTH_BITS, 0,
                              OSMESA_STENCIL_BITS, 0,
                              OSMESA_ACCUM_BITS, 0,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, v[0],
                              OSMESA_CONTEXT_MINOR_VERSION, v[1],
                              0};
    state_->context = OSMesaCreateContextAttribs(attributes, nullptr);
    if (state_->context) break;
  }
  if (!state_->context)
    throw std::runtime_error(
        "OSMesa backend: OSMesaCreateContextAttribs could not create an OpenGL 3.3 core "
        "profile context");
  makeCurrent();
}

OsMesaBackend::~OsMesaBackend() {
  if (state_->context) OSMesaDestroyContext(state_->context);
}

void OsMesaBackend::makeCurrent() {
  if (OSMesaGetCurrentContext() == state_->context) return;
  if (!OSMesaMakeCurrent(state_->context, state_->dummy_buffer.data(), GL_UNSIGNED_BYTE, 1, 1))
    throw std::runtime_error("OSMesa backend: OSMesaMakeCurrent failed");
}

GlBackend::Proc OsMesaBackend::getProcAddress(const char* name) const {
  return reinterpret_cast<Proc>(OSMesaGetProcAddress(name));
}

}  // namespace pbf
