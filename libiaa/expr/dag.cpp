#include "expr/dag.h"

#include <bit>
#include <utility>

#include "core/error.h"

namespace iaa {

std::size_t Dag::KeyHash::operator()(const Key& k) const {
  std::uint64_t h = static_cast<std::uint64_t>(k.op);
  h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.a));
  h = h * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.b));
  h = h * 0x9E3779B97F4A7C15ull ^ k.bits;
  return static_cast<std::size_t>(h ^ (h >> 29));
}

NodeId Dag::intern(const Node& n) {
  const std::uint64_t bits = n.op == Op::kConst ? std::bit_cast<std::uint64_t>(n.value)
                                                : static_cast<std::uint64_t>(n.power);
  const Key key{n.op, n.a, n.b, bits};
  auto it = index_.find(key);
  if (it != index_.end()) return it->second;
  const auto id = static_cast<NodeId>(nodes_.size());
  nodes_.push_back(n);
  index_.emplace(key, id);
  return id;
}

NodeId Dag::var(int axis) {
  IAA_CHECK(axis >= 0 && axis < 3);
  static constexpr Op kVars[3] = {Op::kVarX, Op::kVarY, Op::kVarZ};
  return intern(Node{kVars[axis]});
}

NodeId Dag::constant(double v) {
  if (v == 0.0) v = 0.0;  // one node for +0 and -0
  Node n{Op::kConst};
  n.value = v;
  return intern(n);
}

NodeId Dag::unary(Op op, NodeId a) {
  IAA_CHECK(info(op).arity == 1 && op != Op::kPowInt);
  double v;
  // Negating a constant is exact, so it may be folded without losing the guarantee.
  if (op == Op::kNeg && is_constant(a, &v)) return constant(-v);
  return intern(Node{op, a});
}

NodeId Dag::binary(Op op, NodeId a, NodeId b) {
  IAA_CHECK(info(op).arity == 2);
  if (is_commutative(op) && b < a) std::swap(a, b);
  return intern(Node{op, a, b});
}

NodeId Dag::pow_int(NodeId a, int n) {
  IAA_CHECK(n >= 0);
  Node node{Op::kPowInt, a};
  node.power = n;
  return intern(node);
}

bool Dag::is_constant(NodeId id, double* v) const {
  const Node& n = node(id);
  if (n.op != Op::kConst) return false;
  *v = n.value;
  return true;
}

}  // namespace iaa
