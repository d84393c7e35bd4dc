#include "expr/specialize.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace iaa {

namespace {

/// True when x is a single number up to a few rounding errors of its size.
bool is_point(const Interval& x) {
  return x.hi() - x.lo() <=
         0x1p-40 * std::fmax(1.0, std::fmax(std::fabs(x.lo()), std::fabs(x.hi())));
}

std::vector<std::int32_t> min_max_instructions(const Tape& t) {
  std::vector<std::int32_t> out;
  const auto ins = t.instrs();
  for (int i = t.first_op(); i < t.size(); ++i) {
    const Op op = ins[static_cast<std::size_t>(i)].op;
    if (op == Op::kMin || op == Op::kMax) out.push_back(i);
  }
  return out;
}

}  // namespace

SpecializingEval::Variant::Variant(std::vector<std::uint8_t> k, std::unique_ptr<Tape> t,
                                   std::vector<std::int32_t> o)
    : key(std::move(k)),
      tape(std::move(t)),
      origin(std::move(o)),
      undecided(min_max_instructions(*tape)),
      ie(*tape),
      ig(*tape),
      pe(*tape),
      pg(*tape) {}

SpecializingEval::SpecializingEval(const Tape& tape) : tape_(&tape) {
  std::vector<std::int32_t> identity(static_cast<std::size_t>(tape.size()));
  for (std::size_t i = 0; i < identity.size(); ++i) identity[i] = static_cast<std::int32_t>(i);
  variants_.push_back(std::make_unique<Variant>(std::vector<std::uint8_t>(identity.size(), 0),
                                                std::make_unique<Tape>(tape), std::move(identity)));
}

void SpecializingEval::reset() {
  regions_ = {};
  variants_.resize(1);
}

SpecializingEval::Variant& SpecializingEval::variant_for(const IBox& b) {
  // An empty side counts as inside any interval (Interval::contains): the whole tape then.
  if (b.is_empty()) return *variants_[0];
  for (const Region& r : regions_) {
    if (r.variant < 0) break;
    if (r.box.contains(b)) {
      ++specialized_evals_;
      return *variants_[static_cast<std::size_t>(r.variant)];
    }
  }
  return *variants_[0];
}

SpecializingEval::Variant& SpecializingEval::variant_for(const IBox* boxes, int n) {
  if (regions_[0].variant < 0) return *variants_[0];  // no region yet (or no min/max at all)
  for (int j = 0; j < n; ++j) {
    if (boxes[j].is_empty()) return *variants_[0];
  }
  for (const Region& r : regions_) {
    if (r.variant < 0) break;
    bool all = true;
    for (int j = 0; j < n && all; ++j) all = r.box.contains(boxes[j]);
    if (all) {
      specialized_evals_ += static_cast<std::uint64_t>(n);
      return *variants_[static_cast<std::size_t>(r.variant)];
    }
  }
  return *variants_[0];
}

namespace {
/// Runs `batch` (made from `tape` on first use, with the batches' instruction set) over the
/// boxes, and reads its partial-domain flags.
template <class Batch, class Out>
void run_batch(std::unique_ptr<Batch>& batch, const Tape& tape, bool baseline, const IBox* boxes,
               int n, Out* out, bool* partial) {
  if (!batch) {
    batch = std::make_unique<Batch>(tape);
    batch->use_baseline(baseline);
  }
  batch->eval(boxes, n, out);
  for (int j = 0; j < n; ++j) partial[j] = batch->partial_domain(j);
}
}  // namespace

void SpecializingEval::eval_batch(const IBox* boxes, int n, Interval* out, bool* partial) {
  Variant& v = variant_for(boxes, n);
  run_batch(v.be, *v.tape, baseline_, boxes, n, out, partial);
}

void SpecializingEval::eval_grad_batch(const IBox* boxes, int n, IGrad* out, bool* partial) {
  Variant& v = variant_for(boxes, n);
  run_batch(v.bg, *v.tape, baseline_, boxes, n, out, partial);
}

void SpecializingEval::use_baseline(bool baseline) {
  baseline_ = baseline;
  for (auto& v : variants_) {
    if (v->be) v->be->use_baseline(baseline);
    if (v->bg) v->bg->use_baseline(baseline);
  }
}

SpecializingEval::Variant& SpecializingEval::variant_at(const Vec3& p) {
  for (const Region& r : regions_) {
    if (r.variant < 0) break;
    if (r.box.contains(p)) return *variants_[static_cast<std::size_t>(r.variant)];
  }
  return *variants_[0];
}

void SpecializingEval::learn(const IBox& b, const Variant& v,
                             const std::vector<std::uint8_t>& choices) {
  // A point (up to the rounding of its coordinates) makes no region: hardly another box lies
  // inside it, and it would push out the regions of the pieces and beams around it.
  if (is_point(b.x) && is_point(b.y) && is_point(b.z)) return;
  bool more = false;
  for (const std::int32_t i : v.undecided) more |= choices[static_cast<std::size_t>(i)] != 0;
  if (!more) return;
  key_ = v.key;
  for (const std::int32_t i : v.undecided) {
    const std::uint8_t c = choices[static_cast<std::size_t>(i)];
    if (c != 0) key_[static_cast<std::size_t>(v.origin[static_cast<std::size_t>(i)])] = c;
  }
  int found = -1;
  for (std::size_t k = 1; k < variants_.size() && found < 0; ++k) {
    if (variants_[k]->key == key_) found = static_cast<int>(k);
  }
  if (found < 0) {
    if (static_cast<int>(variants_.size()) > kMaxVariants) return;
    std::vector<std::int32_t> origin;
    auto t = std::make_unique<Tape>(tape_->simplify(key_, &origin));
    variants_.push_back(std::make_unique<Variant>(key_, std::move(t), std::move(origin)));
    found = static_cast<int>(variants_.size()) - 1;
  }
  // The newest region first; the oldest is forgotten.
  std::move_backward(regions_.begin(), regions_.end() - 1, regions_.end());
  regions_[0] = Region{b, found};
}

Interval SpecializingEval::eval(const IBox& b) {
  Variant& v = variant_for(b);
  const Interval f = v.ie.eval(b);
  partial_ = v.ie.partial_domain();
  if (!v.undecided.empty() && !partial_ && !f.is_empty()) learn(b, v, v.ie.choices());
  return f;
}

IGrad SpecializingEval::eval_grad(const IBox& b) {
  Variant& v = variant_for(b);
  const IGrad g = v.ig.eval(b);
  partial_ = v.ig.partial_domain();
  if (!v.undecided.empty() && !partial_ && !g.v.is_empty()) learn(b, v, v.ig.choices());
  return g;
}

}  // namespace iaa
