#include "iaa/command_spread.h"

#include <atomic>
#include <cstdlib>
#include <string>

#include "core/error.h"

namespace iaa::cli {
namespace {

/// A spread that fails on purpose at its second request for an item (command_spread()).
class FailingSpread final : public Spread {
 public:
  explicit FailingSpread(std::unique_ptr<Spread> inner) : inner_(std::move(inner)) {}
  int size() const override { return inner_->size(); }
  int rank() const override { return inner_->rank(); }
  void begin(std::uint64_t items, const ProgressPhase* phase) override {
    inner_->begin(items, phase);
  }
  std::int64_t next() override {
    if (++requests_ == 2) {
      throw Error("failed on purpose for a test (IAA_TEST_FAIL_RANK=" + std::to_string(rank()) +
                  ")");
    }
    return inner_->next();
  }
  void fail() override { inner_->fail(); }
  SpreadBalance finish(std::vector<std::string>& results,
                       std::vector<std::uint64_t>& work) override {
    return inner_->finish(results, work);
  }

 private:
  std::unique_ptr<Spread> inner_;
  std::atomic<int> requests_{0};
};

}  // namespace

std::unique_ptr<Spread> command_spread(dist::World* world) {
  if (!world) return nullptr;
  std::unique_ptr<Spread> spread = world->spread();
  const char* fail = std::getenv("IAA_TEST_FAIL_RANK");
  if (spread && fail && std::atoi(fail) == world->rank()) {
    return std::make_unique<FailingSpread>(std::move(spread));
  }
  return spread;
}

}  // namespace iaa::cli
