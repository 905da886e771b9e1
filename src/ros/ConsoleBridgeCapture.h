#pragma once
// urdf and geometric_shapes say why they failed only through console_bridge's log. While
// one of these is alive, that log is collected here instead of printed, so the reason can
// go into our own message (which names the link).

#include <console_bridge/console.h>

#include <string>

namespace pbf_ros {

class ConsoleBridgeCapture : public console_bridge::OutputHandler {
 public:
  ConsoleBridgeCapture() { console_bridge::useOutputHandler(this); }
  ~ConsoleBridgeCapture() override { console_bridge::restorePreviousOutputHandler(); }
  ConsoleBridgeCapture(const ConsoleBridgeCapture&) = delete;
  ConsoleBridgeCapture& operator=(const ConsoleBridgeCapture&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_WARN) return;
    if (!text_.empty()) text_ += "; ";
    text_ += text;
  }
  // What was logged (warnings and errors), trailing newlines removed.
  std::string text() const {
    std::string t = text_;
    while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
    return t;
  }

 private:
  std::string text_;
};

}  // namespace pbf_ros
