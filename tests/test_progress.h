// A Progress for tests of cancellation: it asks the computation to stop as soon as its first phase
// starts, so a computation that checks for cancellation throws, and one that does not finishes.
#pragma once

#include <cstdint>
#include <string_view>

#include "core/exec.h"

namespace iaa::test {

struct CancelAtStart : Progress {
  void start(std::string_view, std::uint64_t) override { cancel(); }
};

}  // namespace iaa::test
