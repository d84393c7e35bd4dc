// When EvalRaySet (beam.cpp) tries the mean-value form of a depth piece or slice, and when it
// evaluates the gradient at once: a record kept per unit of work of the renderer.
#pragma once

#include <algorithm>

namespace iaa {

/// When the mean-value form is tried (beam.cpp). It costs a gradient evaluation and a point
/// evaluation; on some surfaces it almost never excludes what the natural enclosure keeps (huge,
/// fast-varying gradients, as on the twist's thin blades), on others most of the time (the
/// dependency of low-degree polynomials such as chubs). It is tried freely for the first kTrial
/// times, then only while at least 1 in kRate tries excludes 0.
///
/// A unit of work (a screen block, a pixel with its sub-beams) starts with the record of the
/// block just above it (inherited()): where the block's tries failed, the unit gets kFresh free
/// tries instead of kTrial, so that a pixel where they hardly ever pay does not spend kTrial
/// gradient evaluations on them; where they paid, it goes on trying. The chain of blocks above a
/// pixel is fixed (render.cpp), so no decision depends on threads or on which pixels came
/// before, and render_pixel() sees the same budget as render(). Skipping a mean-value form only
/// gives up an exclusion, never claims one.
///
/// Where the natural enclosure of narrow depth pieces (or of slices) keeps 0 at least 7 times
/// in 8, those are evaluated with the gradient at once (gradient_first()): the value part of that
/// evaluation is the same natural enclosure, so a plain evaluation is saved. A unit inherits
/// these counts too (over at most kTrial). docs/render.md gives the measurements behind the
/// constants.
struct MeanValueBudget {
  static constexpr int kTrial = 8;
  static constexpr int kRate = 8;
  static constexpr int kFresh = 4;
  enum Kind { kPiece = 0, kSlice = 1 };
  int tries = 0, hits = 0;  ///< mean-value forms tried, and how many excluded 0
  int seen[2] = {0, 0};     ///< natural enclosures of narrow pieces / slices
  int natural[2] = {0, 0};  ///< ... and how many of them excluded 0
  bool allowed() const { return tries < kTrial || hits * kRate >= tries; }
  bool gradient_first(Kind k) const {
    return allowed() && seen[k] >= kTrial && natural[k] * kRate <= seen[k];
  }
  void record(bool excluded) {
    ++tries;
    hits += excluded;
  }
  void record_natural(Kind k, bool excluded) {
    ++seen[k];
    natural[k] += excluded;
  }
  /// The budget a unit of work inside this one starts with: this one's rate of hits over at most
  /// kTrial - kFresh tries, so that a failed record still leaves kFresh free tries; and its
  /// record of natural enclosures over at most kTrial of them, so that a unit inside a block
  /// whose narrow pieces (or slices) the natural enclosure hardly ever excluded takes their
  /// gradient at once (a pixel searches only a few narrow pieces, too few to learn it itself).
  MeanValueBudget inherited() const {
    MeanValueBudget b;
    b.tries = std::min(tries, kTrial - kFresh);
    if (tries > 0) {
      // The same rate of hits, rounded so that a record that allows tries still does.
      const int scaled = hits * b.tries;
      b.hits = hits * kRate >= tries ? (scaled + tries - 1) / tries : scaled / tries;
    }
    for (int k = 0; k < 2; ++k) {
      b.seen[k] = std::min(seen[k], kTrial);
      if (seen[k] > 0) {
        // The same rate, rounded so that a record that takes the gradient first still does.
        const int scaled = natural[k] * b.seen[k];
        b.natural[k] =
            natural[k] * kRate <= seen[k] ? scaled / seen[k] : (scaled + seen[k] - 1) / seen[k];
      }
    }
    return b;
  }
};

}  // namespace iaa
