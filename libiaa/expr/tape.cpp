#include "expr/tape.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>
#include <utility>

#include "core/error.h"

namespace iaa {

Tape Tape::compile(const Dag& dag) {
  IAA_CHECK(dag.root >= 0 && static_cast<std::size_t>(dag.root) < dag.size());
  // Mark the nodes the root reaches; nodes are in topological order, so one backward pass does.
  std::vector<char> live(dag.size(), 0);
  live[static_cast<std::size_t>(dag.root)] = 1;
  for (std::size_t i = dag.size(); i-- > 0;) {
    if (!live[i]) continue;
    const Node& n = dag.node(static_cast<NodeId>(i));
    if (n.a >= 0) live[static_cast<std::size_t>(n.a)] = 1;
    if (n.b >= 0) live[static_cast<std::size_t>(n.b)] = 1;
  }

  Tape t;
  std::vector<std::int32_t> slot(dag.size(), -1);
  t.instrs_ = {Instr{Op::kVarX}, Instr{Op::kVarY}, Instr{Op::kVarZ}};
  t.constants_ = {0.0, 0.0, 0.0};
  // Variables and constants first, then the operations in topological order.
  for (std::size_t i = 0; i < dag.size(); ++i) {
    if (!live[i]) continue;
    const Node& n = dag.node(static_cast<NodeId>(i));
    if (n.op == Op::kVarX) slot[i] = 0;
    if (n.op == Op::kVarY) slot[i] = 1;
    if (n.op == Op::kVarZ) slot[i] = 2;
    if (n.op == Op::kConst) {
      slot[i] = static_cast<std::int32_t>(t.instrs_.size());
      t.instrs_.push_back(Instr{Op::kConst});
      t.constants_.push_back(n.value);
    }
  }
  t.first_op_ = static_cast<int>(t.instrs_.size());
  // sin(a) and cos(a) of the same a (one node each: the DAG merges repeats) become one sincos
  // pair, emitted where the first of the two stands (a is before both).
  std::unordered_map<NodeId, std::size_t> sin_of;
  std::vector<std::int64_t> cos_partner(dag.size(), -1);
  for (std::size_t i = 0; i < dag.size(); ++i) {
    if (live[i] && dag.node(static_cast<NodeId>(i)).op == Op::kSin)
      sin_of[dag.node(static_cast<NodeId>(i)).a] = i;
  }
  for (std::size_t i = 0; i < dag.size(); ++i) {
    const Node& n = dag.node(static_cast<NodeId>(i));
    if (!live[i] || n.op != Op::kCos) continue;
    const auto it = sin_of.find(n.a);
    if (it == sin_of.end()) continue;
    cos_partner[it->second] = static_cast<std::int64_t>(i);
    cos_partner[i] = static_cast<std::int64_t>(it->second);
  }
  for (std::size_t i = 0; i < dag.size(); ++i) {
    if (!live[i] || slot[i] >= 0) continue;
    const Node& n = dag.node(static_cast<NodeId>(i));
    if (cos_partner[i] >= 0) {
      const auto j = static_cast<std::size_t>(cos_partner[i]);
      const std::size_t sin_node = n.op == Op::kSin ? i : j;
      const std::size_t cos_node = n.op == Op::kSin ? j : i;
      Instr ins{Op::kSinCos};
      ins.a = slot[static_cast<std::size_t>(n.a)];
      slot[sin_node] = static_cast<std::int32_t>(t.instrs_.size());
      t.instrs_.push_back(ins);
      ins.op = Op::kPairedCos;
      slot[cos_node] = static_cast<std::int32_t>(t.instrs_.size());
      t.instrs_.push_back(ins);
      t.constants_.insert(t.constants_.end(), 2, 0.0);
      continue;
    }
    Instr ins{n.op};
    ins.a = n.a >= 0 ? slot[static_cast<std::size_t>(n.a)] : -1;
    ins.b = n.b >= 0 ? slot[static_cast<std::size_t>(n.b)] : -1;
    ins.power = n.power;
    // A product with a finite non-zero constant becomes `scale`, the constant second.
    const auto finite_nonzero_const = [&](std::int32_t sl) {
      const Instr& c = t.instrs_[static_cast<std::size_t>(sl)];
      const double v = t.constants_[static_cast<std::size_t>(sl)];
      return c.op == Op::kConst && std::isfinite(v) && v != 0.0;
    };
    if (n.op == Op::kMul && finite_nonzero_const(ins.a)) std::swap(ins.a, ins.b);
    if (n.op == Op::kMul && finite_nonzero_const(ins.b)) ins.op = Op::kScale;
    if (n.op == Op::kDiv && finite_nonzero_const(ins.b)) ins.op = Op::kDivConst;
    if (n.op == Op::kMin || n.op == Op::kMax) t.has_min_max_ = true;
    slot[i] = static_cast<std::int32_t>(t.instrs_.size());
    t.instrs_.push_back(ins);
    t.constants_.push_back(0.0);
  }
  t.root_ = slot[static_cast<std::size_t>(dag.root)];
  return t;
}

Tape Tape::parse(std::string_view text, const Params& params) {
  return compile(parse_expression(text, params));
}

std::string Tape::listing() const {
  std::string out;
  char buf[96];
  for (std::size_t i = 0; i < instrs_.size(); ++i) {
    const Instr& in = instrs_[i];
    if (in.op == Op::kConst) {
      std::snprintf(buf, sizeof buf, "%4zu  const  %.17g\n", i, constants_[i]);
    } else if (in.op == Op::kPowInt) {
      std::snprintf(buf, sizeof buf, "%4zu  powi   $%d ^ %d\n", i, in.a, in.power);
    } else if (in.op == Op::kPairedCos) {
      std::snprintf(buf, sizeof buf, "%4zu  cos    $%d  (with the sincos above)\n", i, in.a);
    } else if (info(in.op).arity == 0) {
      std::snprintf(buf, sizeof buf, "%4zu  %s\n", i, std::string(info(in.op).text).c_str());
    } else if (info(in.op).arity == 1) {
      std::snprintf(buf, sizeof buf, "%4zu  %-6s $%d\n", i, std::string(info(in.op).text).c_str(),
                    in.a);
    } else {
      std::snprintf(buf, sizeof buf, "%4zu  %-6s $%d $%d\n", i,
                    std::string(info(in.op).text).c_str(), in.a, in.b);
    }
    out += buf;
  }
  out += "root $" + std::to_string(root_) + "\n";
  return out;
}

Tape Tape::simplify(std::span<const std::uint8_t> choice, std::vector<std::int32_t>* origin) const {
  IAA_CHECK(choice.size() == instrs_.size());
  // Forward the decided min/max to the argument they take, then keep what the root still reaches.
  std::vector<std::int32_t> alias(instrs_.size());
  for (std::size_t i = 0; i < instrs_.size(); ++i) {
    alias[i] = static_cast<std::int32_t>(i);
    const Instr& in = instrs_[i];
    if ((in.op == Op::kMin || in.op == Op::kMax) && choice[i] != 0) {
      alias[i] = alias[static_cast<std::size_t>(choice[i] == 1 ? in.a : in.b)];
    }
  }
  std::vector<char> live(instrs_.size(), 0);
  live[static_cast<std::size_t>(alias[static_cast<std::size_t>(root_)])] = 1;
  for (std::size_t i = instrs_.size(); i-- > 0;) {
    if (!live[i] || alias[i] != static_cast<std::int32_t>(i)) continue;
    const Instr& in = instrs_[i];
    if (in.a >= 0) live[static_cast<std::size_t>(alias[static_cast<std::size_t>(in.a)])] = 1;
    if (in.b >= 0) live[static_cast<std::size_t>(alias[static_cast<std::size_t>(in.b)])] = 1;
  }
  Tape t;
  t.instrs_.clear();
  t.constants_.clear();
  if (origin) origin->clear();
  std::vector<std::int32_t> slot(instrs_.size(), -1);
  const auto kept = [&](std::size_t i) {
    return i < 3 || (live[i] && alias[i] == static_cast<std::int32_t>(i));
  };
  for (std::size_t i = 0; i < instrs_.size(); ++i) {
    if (!kept(i)) continue;
    Instr in = instrs_[i];
    // A sincos pair with one half gone is a plain sin or cos (kept instructions keep their
    // order, so a pair with both halves stays adjacent).
    if (in.op == Op::kSinCos && !kept(i + 1)) in.op = Op::kSin;
    if (in.op == Op::kPairedCos && !kept(i - 1)) in.op = Op::kCos;
    if (in.a >= 0) in.a = slot[static_cast<std::size_t>(alias[static_cast<std::size_t>(in.a)])];
    if (in.b >= 0) in.b = slot[static_cast<std::size_t>(alias[static_cast<std::size_t>(in.b)])];
    if (in.op == Op::kMin || in.op == Op::kMax) t.has_min_max_ = true;
    slot[i] = static_cast<std::int32_t>(t.instrs_.size());
    t.instrs_.push_back(in);
    t.constants_.push_back(constants_[i]);
    if (origin) origin->push_back(static_cast<std::int32_t>(i));
  }
  // first_op: the first slot that is neither a variable nor a constant.
  t.first_op_ = static_cast<int>(t.instrs_.size());
  for (int i = 0; i < static_cast<int>(t.instrs_.size()); ++i) {
    const Op op = t.instrs_[static_cast<std::size_t>(i)].op;
    if (op != Op::kVarX && op != Op::kVarY && op != Op::kVarZ && op != Op::kConst) {
      t.first_op_ = i;
      break;
    }
  }
  t.root_ = slot[static_cast<std::size_t>(alias[static_cast<std::size_t>(root_)])];
  return t;
}

}  // namespace iaa
