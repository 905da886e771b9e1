#pragma once
// GlBackend on EGL's surfaceless Mesa platform: a desktop-GL core context with no window,
// no pbuffer and no device node, drawing only into framebuffer objects.

#include <memory>

#include "pbf_ros/render/GlBackend.h"

namespace pbf {

class EglBackend final : public GlBackend {
 public:
  EglBackend();
  ~EglBackend() override;
  EglBackend(const EglBackend&) = delete;
  EglBackend& operator=(const EglBackend&) = delete;

  void makeCurrent() override;
  Proc getProcAddress(const char* name) const override;
  std::string name() const override { return "egl"; }

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace pbf
