// A private Xvfb server for headless rendering (see xserver.h).
#include "xserver.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <string>

#include "core/error.h"

namespace iaa::viz {

bool have_display() {
  const char* d = std::getenv("DISPLAY");
  return d && *d;
}

bool display_reachable() {
  // The connection is kept open for the life of the process, never closed: when its last client
  // disconnects, an X server started without -noreset (xvfb-run's) resets, and VTK's own
  // connection right after would fail and abort.
  static std::string probed;
  static void* connection = nullptr;
  const char* env = std::getenv("DISPLAY");
  const std::string name = env ? env : "";
  if (connection && probed == name) return true;
  // libX11 is already loaded (VTK's X11 render window links it); looked up at run time so that
  // iaa-viz need not link X11 itself.
  void* x11 = dlopen("libX11.so.6", RTLD_LAZY);
  if (!x11) return true;
  using Open = void* (*)(const char*);
  auto open = reinterpret_cast<Open>(dlsym(x11, "XOpenDisplay"));
  if (!open) return true;
  void* d = open(nullptr);
  if (!d) return false;
  connection = d;
  probed = name;
  return true;
}

std::unique_ptr<PrivateXServer> PrivateXServer::start(int width, int height) {
  int fds[2];
  if (pipe(fds) != 0) throw Error("cannot start Xvfb: pipe() failed");
  const std::string screen =
      std::to_string(std::max(width, 1280)) + "x" + std::to_string(std::max(height, 1024)) + "x24";
  const std::string fd_text = std::to_string(fds[1]);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    throw Error("cannot start Xvfb: fork() failed");
  }
  if (pid == 0) {
    // Child: die with the parent, keep Xvfb's chatter off the terminal, and exec the server.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);
    close(fds[0]);
    const int devnull = open("/dev/null", O_RDWR);
    if (devnull >= 0) {
      dup2(devnull, 0);
      dup2(devnull, 1);
      dup2(devnull, 2);
    }
    execlp("Xvfb", "Xvfb", "-displayfd", fd_text.c_str(), "-screen", "0", screen.c_str(),
           "-nolisten", "tcp", "-noreset", static_cast<char*>(nullptr));
    _exit(127);
  }
  close(fds[1]);

  // Xvfb writes the display number it chose, then a newline, once it accepts connections.
  std::string number;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  bool done = false;
  while (!done) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) break;
    pollfd p{fds[0], POLLIN, 0};
    const int r = poll(&p, 1, static_cast<int>(left));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    char buf[32];
    const ssize_t n = read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the server exited (not installed, or failed)
    for (ssize_t i = 0; i < n; ++i) {
      if (buf[i] == '\n') {
        done = true;
        break;
      }
      number += buf[i];
    }
  }
  close(fds[0]);
  if (!done || number.empty()) {
    kill(pid, SIGTERM);
    int status = 0;
    waitpid(pid, &status, 0);
    const bool missing = WIFEXITED(status) && WEXITSTATUS(status) == 127;
    throw Error(missing ? "no usable X display (DISPLAY unset or unreachable) and Xvfb is not "
                          "installed: install the 'xvfb' package, or run under xvfb-run -a, or "
                          "give a display"
                        : "no usable X display (DISPLAY unset or unreachable) and Xvfb did not "
                          "start; try running under xvfb-run -a");
  }
  const std::string display = ":" + number;
  setenv("DISPLAY", display.c_str(), 1);
  return std::unique_ptr<PrivateXServer>(new PrivateXServer(pid, display));
}

PrivateXServer::~PrivateXServer() {
  kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
  unsetenv("DISPLAY");
}

}  // namespace iaa::viz
