// A small stack of depth pieces for front-to-back bisection. Bisection of a finite range to a
// positive tolerance never holds more than one piece per level plus one, so 128 entries suffice;
// the storage is left uninitialised (this sits in the hottest loop of the renderer).
#pragma once

namespace iaa {

class PieceStack {
 public:
  static constexpr int kCapacity = 128;
  /// False when full: the caller must then treat the piece conservatively (keep it).
  bool push(double a, double b) {
    if (n_ == kCapacity) return false;
    a_[n_] = a;
    b_[n_] = b;
    ++n_;
    return true;
  }
  bool pop(double* a, double* b) {
    if (n_ == 0) return false;
    --n_;
    *a = a_[n_];
    *b = b_[n_];
    return true;
  }
  bool has_room(int k) const { return n_ + k <= kCapacity; }

 private:
  double a_[kCapacity];
  double b_[kCapacity];
  int n_ = 0;
};

}  // namespace iaa
