#pragma once
// GlBackend on Mesa's off-screen library. Kept free of GL headers so that osmesa.h's
// GL/gl.h never meets the core-profile glcorearb.h the renderer uses.

#include <memory>

#include "pbf_ros/render/GlBackend.h"

namespace pbf {

class OsMesaBackend final : public GlBackend {
 public:
  OsMesaBackend();
  ~OsMesaBackend() override;
  OsMesaBackend(const OsMesaBackend&) = delete;
  OsMesaBackend& operator=(const OsMesaBackend&) = delete;

  void makeCurrent() override;
  Proc getProcAddress(const char* name) const override;
  std::string name() const override { return "osmesa"; }

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace pbf
