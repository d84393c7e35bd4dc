#include "app/balance.h"

#include <cstdio>

namespace iaa::app {

nlohmann::json balance_json(const SpreadBalance& b) {
  nlohmann::json ranks = nlohmann::json::array();
  for (std::size_t r = 0; r < b.ranks.size(); ++r) {
    const RankLoad& l = b.ranks[r];
    ranks.push_back({{"rank", r},
                     {"items", l.items},
                     {"evaluations", l.work},
                     {"busy_seconds", l.busy},
                     {"idle_seconds", l.idle}});
  }
  return {{"processes", b.ranks.size()},
          {"max_over_mean_evaluations", b.max_over_mean()},
          {"ranks", ranks}};
}

std::string balance_summary(const SpreadBalance& b) {
  std::size_t worst = 0;
  for (std::size_t r = 0; r < b.ranks.size(); ++r) {
    if (b.ranks[r].idle > b.ranks[worst].idle) worst = r;
  }
  char line[200];
  std::snprintf(line, sizeof line,
                "%zu processes: evaluations max/mean %.3f; most idle: rank %zu, %.3f s of %.3f s",
                b.ranks.size(), b.max_over_mean(), worst,
                b.ranks.empty() ? 0.0 : b.ranks[worst].idle,
                b.ranks.empty() ? 0.0 : b.ranks[worst].idle + b.ranks[worst].busy);
  return line;
}

}  // namespace iaa::app
