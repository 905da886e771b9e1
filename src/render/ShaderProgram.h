#pragma once
// One linked GLSL program built from a vertex and a fragment file of the shader directory.

#include <string>

#include "GlFunctions.h"

namespace pbf {

class ShaderProgram {
 public:
  ShaderProgram() = default;
  // Throws std::runtime_error naming the file and quoting the compile or link log.
  ShaderProgram(const GlFunctions& gl, const std::string& shader_dir,
                const std::string& vertex_file, const std::string& fragment_file);
  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& other) noexcept { *this = std::move(other); }
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  void use() const { gl_->UseProgram(program_); }
  // Location of a uniform; -1 (silently ignored by glUniform*) if the linker removed it.
  GLint uniform(const char* name) const { return gl_->GetUniformLocation(program_, name); }

 private:
  const GlFunctions* gl_ = nullptr;
  GLuint program_ = 0;
};

}  // namespace pbf
