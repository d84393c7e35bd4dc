// Application layer: used by tools/ and viz/, never by the library modules.
// A terminal progress bar implementing iaa::Progress. Draws on stderr only when stderr is a
// terminal (and not when quiet); otherwise it is silent, so logs and CI output stay clean.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

#include "core/exec.h"

namespace iaa::app {

class ProgressBar : public Progress {
 public:
  /// `quiet` forces silence even on a terminal.
  explicit ProgressBar(bool quiet = false);
  ~ProgressBar() override;
  void start(std::string_view phase, std::uint64_t total) override;
  void advance(std::uint64_t n) override;
  void finish() override;

 private:
  void draw(bool final);

  bool enabled_;
  std::string phase_;
  std::uint64_t total_ = 0;
  std::atomic<std::uint64_t> done_{0};
  std::atomic<std::int64_t> last_draw_ns_{0};
  std::chrono::steady_clock::time_point start_;
  std::mutex mu_;
  bool drawn_ = false;
};

}  // namespace iaa::app
