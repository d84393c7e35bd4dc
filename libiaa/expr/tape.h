// A flat tape: the expression compiled to numbered slots, evaluated front to back.
//
// Slots 0, 1, 2 hold x, y, z; the next slots hold the constants; every further slot is the output
// of one instruction whose arguments are earlier slots. Each evaluator (point, interval,
// interval+gradient, point+gradient) owns an array of slots and runs the same tape. The tape is
// the hot loop of everything in iaa.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "expr/dag.h"
#include "expr/opcodes.h"
#include "expr/parser.h"

namespace iaa {

/// One instruction; its output is the slot with the instruction's own index.
struct Instr {
  Op op;
  std::int32_t a = -1;     ///< first argument slot
  std::int32_t b = -1;     ///< second argument slot
  std::int32_t power = 0;  ///< exponent of kPowInt
};

class Tape {
 public:
  /// Compiles the part of `dag` reachable from its root.
  static Tape compile(const Dag& dag);
  /// Parses and compiles; throws ParseError.
  static Tape parse(std::string_view text, const Params& params = {});

  /// All slots; entries below first_op() are kVarX/Y/Z and kConst.
  std::span<const Instr> instrs() const { return instrs_; }
  /// Value of each slot that is a constant (0 for the others).
  std::span<const double> constants() const { return constants_; }
  int size() const { return static_cast<int>(instrs_.size()); }
  /// Index of the first computing instruction.
  int first_op() const { return first_op_; }
  /// Number of computing instructions (the tape's length as a cost measure).
  int op_count() const { return size() - first_op_; }
  /// Slot of the expression's value.
  int root() const { return root_; }
  /// True when the tape contains min or max (branches that intervals may prune).
  bool has_min_max() const { return has_min_max_; }

  /// Expression text that parses back to a tape of the same operations, which evaluates
  /// identically (shared subexpressions are written out, so the full text of a tape with much
  /// sharing can be far longer than the tape). The text nests as little as it can: parentheses
  /// only where precedence needs them, chains of + - * / and the arguments of min/max written
  /// flat, operands of + * min max ordered to keep chains flat (tape_text.cpp). So it nests no
  /// deeper than any text of the same tape, and the parser's limit (kMaxNesting) is met by the
  /// text of every tape parsed from text. When the text is longer than `max_chars`, the result
  /// is its first `max_chars` characters followed by "...". Time and memory are linear in the
  /// length of the result plus the size of the tape.
  std::string to_text(std::size_t max_chars = std::string::npos) const;
  /// A numbered listing, one instruction per line, for `iaa eval --tape`.
  std::string listing() const;

  /// Specializes the tape for a region where some min/max are decided: `choice[i]` is 1 when
  /// instruction i (a min or max) certainly takes its first argument, 2 its second, 0 undecided.
  /// The result computes the same function on that region with fewer instructions. With
  /// `origin`, origin[j] is the instruction of this tape that the result's instruction j came from.
  Tape simplify(std::span<const std::uint8_t> choice,
                std::vector<std::int32_t>* origin = nullptr) const;

 private:
  std::vector<Instr> instrs_;
  std::vector<double> constants_;
  int first_op_ = 3;
  int root_ = 0;
  bool has_min_max_ = false;
};

}  // namespace iaa
