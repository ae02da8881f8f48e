#pragma once
/// Turning a written chain of one operator into binary nodes: o0 op1 o1 op2 o2 … opn on, each op
/// either the direct operation or its inverse (+ and -, * and /; and/or have no inverse), read
/// left to right as written.
///
/// Short chains (up to kChainRun operands) become the left-associated tree the user wrote, so they
/// evaluate exactly as written. A longer chain is split in halves, recursively, into runs of at
/// most kChainRun operands: the tree's depth is about kChainRun + log2(n / kChainRun), so a
/// 100 000-term sum is a tree of depth ~29 and every later recursive pass stays shallow. The
/// regrouping uses  a ± (b ± c …) = a ± b ∓ … : with s_k = +1 for a direct and -1 for an inverse
/// operator (s_0 = +1), the part l..r-1 taken relative to its first operand's sign,
/// V(l, r) = o_l op_{s_l s_{l+1}} o_{l+1} …, satisfies V(l, r) = V(l, m) op_{s_l s_m} V(m, r).

#include <cstddef>
#include <string>
#include <vector>

namespace momenta {

/// Operands run left-associated as written; longer chains are halved (see above).
constexpr size_t kChainRun = 16;

/// Builds the chain. `inverse[k]` says operand k enters through the inverse operator (false for
/// k = 0); `combine(a, inverse, b)` makes one binary node: a op b, or a op^-1 b when `inverse`.
template <class T, class Combine>
T BuildChain(const std::vector<T>& operands, const std::vector<bool>& inverse, const Combine& combine) {
  // V(l, r) relative to the sign of operand l (recursion depth log2(n / kChainRun)).
  auto part = [&](auto&& self, size_t l, size_t r) -> T {
    if (r - l <= kChainRun) {
      T acc = operands[l];
      for (size_t k = l + 1; k < r; ++k) acc = combine(acc, inverse[k] != inverse[l], operands[k]);
      return acc;
    }
    const size_t m = l + (r - l) / 2;
    T left = self(self, l, m);
    T right = self(self, m, r);
    return combine(left, inverse[m] != inverse[l], right);
  };
  return part(part, 0, operands.size());
}

/// Builds an elseif chain from its operands c1, v1, c2, v2, …, e: if c1 then v1 else (if c2 …),
/// nested from the last branch by a loop. `make_if(cond, then_value, else_value)` makes one node.
template <class T, class MakeIf>
T BuildIfChain(const std::vector<T>& operands, const MakeIf& make_if) {
  T r = operands.back();
  for (size_t k = operands.size() - 1; k >= 2; k -= 2) r = make_if(operands[k - 2], operands[k - 1], r);
  return r;
}

/// The `inverse` flags of a kSum or kProduct node from its operator string ('-' or '/' invert).
inline std::vector<bool> InverseFlags(const std::string& ops) {
  std::vector<bool> inverse(ops.size());
  for (size_t k = 0; k < ops.size(); ++k) inverse[k] = ops[k] == '-' || ops[k] == '/';
  return inverse;
}

}  // namespace momenta
