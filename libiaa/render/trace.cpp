// Names of the trace enums, as `iaa inspect` prints them.
#include "render/trace.h"

namespace iaa {

const char* beam_result_name(BeamResult r) {
  switch (r) {
    case BeamResult::kMiss:
      return "miss";
    case BeamResult::kFull:
      return "full";
    case BeamResult::kPartial:
      return "partial";
  }
  return "?";
}

const char* beam_decision_name(BeamDecision d) {
  switch (d) {
    case BeamDecision::kBackground:
      return "background";
    case BeamDecision::kShadeFull:
      return "shade-full";
    case BeamDecision::kShadeLeaf:
      return "shade-leaf";
    case BeamDecision::kSplit:
      return "split";
    case BeamDecision::kDescend:
      return "descend";
  }
  return "?";
}

}  // namespace iaa
