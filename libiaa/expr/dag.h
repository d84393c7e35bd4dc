// Expression DAG with common subexpressions merged (hash-consing): building the same operation on
// the same arguments twice returns the same node. Nodes are stored in creation order, which is a
// topological order (arguments before their users); the tape compiler relies on that.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "expr/opcodes.h"

namespace iaa {

/// Index of a node in a Dag.
using NodeId = std::int32_t;

/// One node: an operation and up to two arguments. `value` is the constant of kConst; `power` the
/// exponent of kPowInt.
struct Node {
  Op op;
  NodeId a = -1;
  NodeId b = -1;
  double value = 0.0;
  int power = 0;
};

class Dag {
 public:
  NodeId var(int axis);
  NodeId constant(double v);
  NodeId unary(Op op, NodeId a);
  NodeId binary(Op op, NodeId a, NodeId b);
  NodeId pow_int(NodeId a, int n);

  const Node& node(NodeId id) const { return nodes_[static_cast<std::size_t>(id)]; }
  std::size_t size() const { return nodes_.size(); }

  /// The constant value of a node when it is a kConst, else false.
  bool is_constant(NodeId id, double* v) const;

  /// The root, set by the parser.
  NodeId root = -1;

 private:
  NodeId intern(const Node& n);

  struct Key {
    Op op;
    NodeId a, b;
    std::uint64_t bits;  // constant bits or power
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  std::vector<Node> nodes_;
  std::unordered_map<Key, NodeId, KeyHash> index_;
};

}  // namespace iaa
