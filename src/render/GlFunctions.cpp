#include "GlFunctions.h"

#include <sstream>
#include <stdexcept>
#include <string>

#include "pbf_ros/render/GlBackend.h"

namespace pbf {

void GlFunctions::load(const GlBackend& backend) {
#define PBF_GL_LOAD_MEMBER(type, member)                                                \
  member = reinterpret_cast<type>(backend.getProcAddress("gl" #member));                \
  if (!member)                                                                         \
    throw std::runtime_error("GL backend '" + backend.name() + "' does not provide gl" \
                             #member);
  PBF_GL_FUNCTION_LIST(PBF_GL_LOAD_MEMBER)
#undef PBF_GL_LOAD_MEMBER
  // getProcAddress may hand out stubs for functions the context lacks: ask the version.
  GLint major = 0;
  GetIntegerv(GL_MAJOR_VERSION, &major);
  if (major >= 4)
    BlendEquationi =
        reinterpret_cast<PFNGLBLENDEQUATIONIPROC>(backend.getProcAddress("glBlendEquationi"));
}

void GlFunctions::check(const char* what) const {
  const GLenum error = GetError();
  if (error == GL_NO_ERROR) return;
  std::ostringstream text;
  text << what << ": GL error 0x" << std::hex << error;
  throw std::runtime_error(text.str());
}

}  // namespace pbf
