// The syntax tree's own functions (core/lang/ast.h): making a node, printing a name and a tree.

#include "core/lang/ast.h"

#include <algorithm>
#include <sstream>
#include <utility>

namespace momenta {

AstPtr MakeAst(Ast::Kind kind, int column, std::string op, std::vector<AstPtr> args) {
  auto a = std::make_shared<Ast>();
  a->kind = kind;
  a->column = column;
  a->op = std::move(op);
  a->args = std::move(args);
  int below = 0;
  for (const AstPtr& x : a->args) below = std::max(below, x->height);
  a->height = below + 1;
  return a;
}

std::string Ast::PathText() const {
  std::string s;
  for (size_t i = 0; i < path.size(); ++i) {
    if (i) s += ".";
    s += path[i].name;
    if (path[i].index) {
      s += '[';
      s += AstToString(*path[i].index);
      if (path[i].index2) s += ", " + AstToString(*path[i].index2);
      s += ']';
    }
  }
  return s;
}

std::string AstToString(const Ast& a) {
  switch (a.kind) {
    case Ast::Kind::kNumber: {
      std::ostringstream s;
      s << a.number;
      return s.str();
    }
    case Ast::Kind::kBool:
      return a.number != 0 ? "true" : "false";
    case Ast::Kind::kName:
      return a.PathText();
    case Ast::Kind::kCall: {
      std::string s = a.op + "(";
      for (size_t i = 0; i < a.args.size(); ++i) {
        if (i) s += ", ";
        s += AstToString(*a.args[i]);
      }
      return s + ")";
    }
    case Ast::Kind::kUnary: {
      std::string s = a.op == "not" ? "not " : "-";
      s += AstToString(*a.args[0]);
      return s;
    }
    case Ast::Kind::kBinary:
    case Ast::Kind::kSum:
    case Ast::Kind::kProduct: {
      // Left-associated: ((a - b) + c).
      const bool chain = a.kind != Ast::Kind::kBinary;
      std::string s = AstToString(*a.args[0]);
      for (size_t i = 1; i < a.args.size(); ++i) {
        std::string op = chain ? std::string(1, a.op[i]) : a.op;
        s = "(" + s + " " + op + " " + AstToString(*a.args[i]) + ")";
      }
      return s;
    }
    case Ast::Kind::kIf: {
      std::string s;
      for (size_t i = 0; i + 1 < a.args.size(); i += 2) {
        s += "if " + AstToString(*a.args[i]) + " then " + AstToString(*a.args[i + 1]) + " else ";
      }
      return s + AstToString(*a.args.back());
    }
    case Ast::Kind::kArray: {
      std::string s = "[";
      for (size_t i = 0; i < a.args.size(); ++i) s += (i ? ", " : "") + AstToString(*a.args[i]);
      return s + "]";
    }
  }
  return "";
}

}  // namespace momenta
