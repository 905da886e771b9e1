#pragma once
// The OpenGL entry points the renderer uses, loaded through GlBackend::getProcAddress.
//
// Calls read gl.Viewport(...) instead of glViewport(...): nothing here links to a GL
// library, so there is no global symbol that could resolve to the wrong dispatch table.

#include <GL/glcorearb.h>

namespace pbf {

class GlBackend;

// X(type, name) for every function; the member is the name without its "gl" prefix.
#define PBF_GL_FUNCTION_LIST(X)                                       \
  X(PFNGLGETSTRINGPROC, GetString)                                     \
  X(PFNGLGETERRORPROC, GetError)                                       \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                 \
  X(PFNGLVIEWPORTPROC, Viewport)                                       \
  X(PFNGLCLEARCOLORPROC, ClearColor)                                   \
  X(PFNGLCLEARPROC, Clear)                                             \
  X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                             \
  X(PFNGLENABLEPROC, Enable)                                           \
  X(PFNGLSCISSORPROC, Scissor)                                         \
  X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer)                         \
  X(PFNGLDISABLEPROC, Disable)                                         \
  X(PFNGLBLENDFUNCPROC, BlendFunc)                                     \
  X(PFNGLBLENDEQUATIONPROC, BlendEquation)                             \
  X(PFNGLFINISHPROC, Finish)                                           \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                   \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                 \
  X(PFNGLREADBUFFERPROC, ReadBuffer)                                   \
  X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                                 \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                 \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                           \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                 \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                             \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                   \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                             \
  X(PFNGLTEXBUFFERPROC, TexBuffer)                                     \
  X(PFNGLGENERATEMIPMAPPROC, GenerateMipmap)                           \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                         \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                   \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                         \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)               \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)           \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                         \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                   \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                         \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                   \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                             \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                   \
  X(PFNGLBUFFERDATAPROC, BufferData)                                   \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                   \
  X(PFNGLCREATESHADERPROC, CreateShader)                               \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                               \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                             \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                 \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                       \
  X(PFNGLDELETESHADERPROC, DeleteShader)                               \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                             \
  X(PFNGLATTACHSHADERPROC, AttachShader)                               \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                 \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                               \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                     \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                             \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                   \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                   \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                     \
  X(PFNGLUNIFORM2IPROC, Uniform2i)                                     \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                     \
  X(PFNGLUNIFORM2FPROC, Uniform2f)                                     \
  X(PFNGLUNIFORM2FVPROC, Uniform2fv)                                   \
  X(PFNGLUNIFORM3FPROC, Uniform3f)                                     \
  X(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv)                       \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)

struct GlFunctions {
#define PBF_GL_DECLARE_MEMBER(type, name) type name = nullptr;
  PBF_GL_FUNCTION_LIST(PBF_GL_DECLARE_MEMBER)
#undef PBF_GL_DECLARE_MEMBER

  // OpenGL 4.0 (per-draw-buffer blend equations): null on a 3.3 context.
  PFNGLBLENDEQUATIONIPROC BlendEquationi = nullptr;

  // Loads every function from the backend's current context. Throws std::runtime_error
  // naming the first function the context does not provide.
  void load(const GlBackend& backend);

  // Throws std::runtime_error("<what>: GL error 0x...") if GL has recorded an error.
  void check(const char* what) const;
};

}  // namespace pbf
