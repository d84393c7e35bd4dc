// libFuzzer target: any byte string is either rejected with a ParseError or compiles to a tape
// whose point values lie inside its interval values on a box around the point. Anything else
// (a crash, a sanitizer report, another exception, a containment failure) is a finding.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "core/error.h"
#include "expr/eval_interval.h"
#include "expr/eval_point.h"
#include "expr/tape.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const iaa::Tape tape = iaa::Tape::parse(text, {{"r", 0.5}});
    iaa::PointEval pe(tape);
    iaa::IntervalEval ie(tape);
    const iaa::IBox box(iaa::Interval(-1, 1), iaa::Interval(-0.5, 0.25), iaa::Interval(0.1, 2));
    const iaa::Interval v = ie.eval(box);
    const double corners[][3] = {{-1, -0.5, 0.1}, {1, 0.25, 2}, {0, 0, 1}, {0.3, -0.1, 0.7}};
    for (const auto& c : corners) {
      const double p = pe.eval(c[0], c[1], c[2]);
      if (std::isfinite(p) && !v.contains(p)) std::abort();
    }
  } catch (const iaa::ParseError&) {
  } catch (const iaa::Error&) {
  }
  return 0;
}
