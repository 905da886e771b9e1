#include "ShaderProgram.h"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace pbf {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error("cannot read shader file " + path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// GLSL has no #include; shaders that share code (the procedural scene) use
// `#include "file.glsl"` on a line of its own, resolved here, one level deep, relative to
// the shader directory.
std::string readWithIncludes(const std::string& dir, const std::string& path) {
  std::istringstream lines(readFile(path));
  std::ostringstream source;
  const std::string directive = "#include \"";
  for (std::string line; std::getline(lines, line);) {
    if (line.compare(0, directive.size(), directive) == 0) {
      const std::size_t end = line.find('"', directive.size());
      if (end == std::string::npos)
        throw std::runtime_error("shader " + path + ": malformed line '" + line + "'");
      source << readFile(dir + "/" + line.substr(directive.size(), end - directive.size()));
    } else {
      source << line << '\n';
    }
  }
  return source.str();
}

GLuint compile(const GlFunctions& gl, GLenum stage, const std::string& dir,
               const std::string& path) {
  const std::string source = readWithIncludes(dir, path);
  const GLuint shader = gl.CreateShader(stage);
  const char* text = source.c_str();
  gl.ShaderSource(shader, 1, &text, nullptr);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<std::size_t>(length) + 1, '\0');
    gl.GetShaderInfoLog(shader, length, nullptr, log.data());
    gl.DeleteShader(shader);
    throw std::runtime_error("shader " + path + " does not compile:\n" + log.data());
  }
  return shader;
}

}  // namespace

ShaderProgram::ShaderProgram(const GlFunctions& gl, const std::string& shader_dir,
                             const std::string& vertex_file, const std::string& fragment_file)
    : gl_(&gl) {
  const std::string vertex_path = shader_dir + "/" + vertex_file;
  const std::string fragment_path = shader_dir + "/" + fragment_file;
  const GLuint vertex = compile(gl, GL_VERTEX_SHADER, shader_dir, vertex_path);
  GLuint fragment = 0;
  try {
    fragment = compile(gl, GL_FRAGMENT_SHADER, shader_dir, fragment_path);
  } catch (...) {
    gl.DeleteShader(vertex);
    throw;
  }
  program_ = gl.CreateProgram();
  gl.AttachShader(program_, vertex);
  gl.AttachShader(program_, fragment);
  gl.LinkProgram(program_);
  gl.DeleteShader(vertex);
  gl.DeleteShader(fragment);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    gl.GetProgramiv(program_, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<std::size_t>(length) + 1, '\0');
    gl.GetProgramInfoLog(program_, length, nullptr, log.data());
    gl.DeleteProgram(program_);
    program_ = 0;
    throw std::runtime_error("shaders " + vertex_path + " + " + fragment_path +
                             " do not link:\n" + log.data());
  }
}

ShaderProgram::~ShaderProgram() {
  if (program_) gl_->DeleteProgram(program_);
}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this != &other) {
    if (program_) gl_->DeleteProgram(program_);
    gl_ = other.gl_;
    program_ = other.program_;
    other.program_ = 0;
  }
  return *this;
}

}  // namespace pbf
