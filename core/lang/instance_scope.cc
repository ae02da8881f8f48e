#include "core/lang/instance_scope.h"

#include <utility>
#include <vector>

#include "core/lang/parser.h"

namespace momenta {

namespace {

AstPtr WithPrefix(const AstPtr& a, const std::vector<NameSegment>& prefix) {
  if (!a) return a;
  auto out = std::make_shared<Ast>(*a);
  if (a->kind == Ast::Kind::kName) {
    const bool global = a->path.size() == 1 && !a->path[0].index &&
                        (a->path[0].name == "time" || a->path[0].name == "pi");
    if (!global) {
      std::vector<NameSegment> path = prefix;
      for (NameSegment s : a->path) {
        s.index = WithPrefix(s.index, prefix);
        s.index2 = WithPrefix(s.index2, prefix);
        path.push_back(std::move(s));
      }
      out->path = std::move(path);
    }
  }
  for (AstPtr& arg : out->args) arg = WithPrefix(arg, prefix);
  return out;
}

}  // namespace

AstPtr InInstanceScope(const AstPtr& expr, const std::string& instance_path, const SourceLoc& loc) {
  const AstPtr path = ParseName(instance_path, loc);
  return WithPrefix(expr, path->path);
}

}  // namespace momenta
