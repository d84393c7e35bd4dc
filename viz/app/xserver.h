// A private Xvfb server for headless rendering. Debian's VTK renders through X11/GLX only, so
// when DISPLAY is unset iaa-viz starts its own virtual X server, points DISPLAY at it, and stops
// it when done. The server picks a free display number itself (-displayfd), so several iaa-viz
// runs at once (parallel tests) never race for the same number.
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>

namespace iaa::viz {

class PrivateXServer {
 public:
  /// Starts Xvfb with a screen of at least width x height pixels and sets DISPLAY to it.
  /// Throws iaa::Error when Xvfb is missing or does not start within a few seconds.
  static std::unique_ptr<PrivateXServer> start(int width, int height);

  /// Stops the server (SIGTERM, then waits for it).
  ~PrivateXServer();
  PrivateXServer(const PrivateXServer&) = delete;
  PrivateXServer& operator=(const PrivateXServer&) = delete;

  /// The display name, e.g. ":3".
  const std::string& display() const { return display_; }

 private:
  PrivateXServer(pid_t pid, std::string display) : pid_(pid), display_(std::move(display)) {}
  pid_t pid_;
  std::string display_;
};

/// True when DISPLAY is set and not empty.
bool have_display();

/// True when the X display that DISPLAY names accepts a connection (XOpenDisplay through the
/// libX11 that VTK loads). VTK aborts the process when it cannot open its window's display, so
/// this is asked first. Also true when libX11 cannot be found (VTK then decides). A successful
/// probe keeps its connection open until the process ends (see xserver.cpp).
bool display_reachable();

}  // namespace iaa::viz
