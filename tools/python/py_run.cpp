// Running the library's work off the Python thread (py_common.h's run_cancellable), and JSON
// reports as Python objects.
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#include "core/error.h"
#include "py_common.h"

namespace iaa::py {
namespace {

/// The library reports from its worker threads; the Python thread reads a snapshot.
class PolledProgress : public Progress {
 public:
  void start(std::string_view phase, std::uint64_t total) override {
    std::lock_guard<std::mutex> lock(mu_);
    phase_ = phase;
    total_ = total;
    done_.store(0, std::memory_order_relaxed);
  }
  void advance(std::uint64_t n) override { done_.fetch_add(n, std::memory_order_relaxed); }

  /// Calls progress(phase, done, total) with the current state (the GIL held).
  void report(const pb::object& progress) {
    std::string phase;
    std::uint64_t total = 0;
    {
      std::lock_guard<std::mutex> lock(mu_);
      phase = phase_;
      total = total_;
    }
    progress(phase, done_.load(std::memory_order_relaxed), total);
  }

 private:
  std::mutex mu_;
  std::string phase_;
  std::uint64_t total_ = 0;
  std::atomic<std::uint64_t> done_{0};
};

/// One piece of work on its own thread, and the calling thread's wait for it.
class Worker {
 public:
  Worker(const std::function<void(const Exec&)>& work, const Exec& exec)
      : thread_([this, &work, exec] {
          try {
            work(exec);
          } catch (...) {
            error_ = std::current_exception();
          }
          std::lock_guard<std::mutex> lock(mu_);
          done_ = true;
          cv_.notify_all();
        }) {}
  ~Worker() { join(); }

  /// Waits up to `ms` milliseconds with the GIL released; true when the work is over.
  bool wait(int ms) {
    pb::gil_scoped_release release;
    std::unique_lock<std::mutex> lock(mu_);
    return cv_.wait_for(lock, std::chrono::milliseconds(ms), [this] { return done_; });
  }
  /// Waits for the end of the work with the GIL released.
  void join() {
    if (!thread_.joinable()) return;
    pb::gil_scoped_release release;
    thread_.join();
  }
  std::exception_ptr error() const { return error_; }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  bool done_ = false;
  std::exception_ptr error_;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace

void run_cancellable(const std::function<void(const Exec&)>& work, int threads,
                     const pb::object& progress) {
  if (threads < 0 || threads > 1024) {
    throw SettingError("threads must be in [0, 1024] (0 = all cores), got " +
                       std::to_string(threads));
  }
  PolledProgress polled;
  Exec exec;
  exec.threads = threads;
  exec.progress = &polled;
  Worker worker(work, exec);
  for (bool over = false; !over;) {
    over = worker.wait(50);
    try {
      if (PyErr_CheckSignals() != 0) throw pb::error_already_set();
      if (!progress.is_none()) polled.report(progress);
    } catch (...) {
      polled.cancel();  // the work stops at its next check; its own result is dropped
      worker.join();
      throw;
    }
  }
  worker.join();
  if (worker.error()) std::rethrow_exception(worker.error());
}

pb::object to_python(const nlohmann::json& j) {
  // Through Python's json module: exact for every number nlohmann writes (shortest round trip).
  return pb::module_::import("json").attr("loads")(j.dump());
}

}  // namespace iaa::py
