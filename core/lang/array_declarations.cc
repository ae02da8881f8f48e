// Scalar declarations of a type or the model (core/lang/array_declarations.h).

#include "core/lang/array_declarations.h"

#include <utility>

#include "core/lang/parser.h"

namespace momenta {

namespace {

/// The shape of an array literal as written (before any name is looked up), or empty.
Shape LiteralShape(const AstPtr& a) {
  if (!a || a->kind != Ast::Kind::kArray) return {};
  Shape s{static_cast<int>(a->args.size())};
  if (a->args[0]->kind == Ast::Kind::kArray) s.push_back(static_cast<int>(a->args[0]->args.size()));
  return s;
}

}  // namespace

std::vector<AstPtr> DeclarationScalariser::Fill(const AstPtr& a, const std::string& text,
                                                const SourceLoc& loc, const Shape& shape,
                                                const std::string& what) {
  ArrayEvaluator ev(scope_, text, loc);
  ArrayValue v = ev.Eval(a);
  if (v.scalar()) return std::vector<AstPtr>(ElementCount(shape), v.elements[0]);
  if (v.shape != shape) {
    ev.Fail(a->column,
            what + " has shape " + ShapeText(v.shape) + ", but " +
                (shape.empty() ? "it is a scalar (declare shape: " + ShapeText(v.shape) + ")"
                               : "it is declared with shape " + ShapeText(shape)));
  }
  return v.elements;
}

std::vector<ParameterDecl> DeclarationScalariser::Parameters(
    const std::vector<ParameterDecl>& params) {
  // Shapes first (declared, or of a literal value), so that values may use later arrays.
  for (const auto& p : params) {
    Shape s = p.shape.empty() ? LiteralShape(p.value) : p.shape;
    if (!s.empty()) (*table_)[p.name] = s;
  }
  std::vector<ParameterDecl> out;
  for (const auto& p : params) {
    auto found = table_->find(p.name);
    Shape shape = found == table_->end() ? Shape{} : found->second;
    if (shape.empty()) {
      // A parameter without shape whose value is an array expression takes its shape.
      ArrayEvaluator ev(scope_, p.value_text, p.loc);
      ArrayValue v = ev.Eval(p.value);
      if (v.scalar()) {
        out.push_back(p);
        out.back().value = v.elements[0];
        continue;
      }
      shape = (*table_)[p.name] = v.shape;
    }
    std::vector<AstPtr> values =
        Fill(p.value, p.value_text, p.loc, shape, "the value of " + Who(p.name));
    for (size_t i = 0; i < values.size(); ++i) {
      ParameterDecl e = p;
      e.name = ElementName(p.name, shape, i);
      e.value = values[i];
      e.value_text = AstToString(*values[i]);
      e.shape.clear();
      out.push_back(std::move(e));
    }
  }
  return out;
}

std::vector<VariableDecl> DeclarationScalariser::Variables(const std::vector<VariableDecl>& vars,
                                                           const ArrayShapes& signals) {
  for (const auto& v : vars) {
    auto sig = signals.find(v.name);
    if (sig != signals.end() && !v.shape.empty() && v.shape != sig->second) {
      throw ModelError(v.loc, Who(v.name) + " is declared with shape " + ShapeText(v.shape) +
                                  ", but its connector has shape " + ShapeText(sig->second));
    }
    if (!v.shape.empty()) (*table_)[v.name] = v.shape;
  }
  std::vector<VariableDecl> out;
  for (const auto& v : vars) {
    auto sig = signals.find(v.name);
    const Shape shape = sig != signals.end() ? sig->second : v.shape;
    if (shape.empty()) {
      out.push_back(v);
      if (v.start) {
        ArrayEvaluator ev(scope_, AstToString(*v.start), v.loc);
        out.back().start = ev.Scalar(v.start, "the start value of " + Who(v.name));
      }
      continue;
    }
    std::vector<AstPtr> starts;
    if (v.start)
      starts =
          Fill(v.start, AstToString(*v.start), v.loc, shape, "the start value of " + Who(v.name));
    for (size_t i = 0; i < ElementCount(shape); ++i) {
      VariableDecl e = v;
      e.name = ElementName(v.name, shape, i);
      if (v.start) e.start = starts[i];
      e.shape.clear();
      out.push_back(std::move(e));
    }
  }
  return out;
}

std::vector<EquationDecl> DeclarationScalariser::Equations(const std::vector<EquationDecl>& eqs) {
  std::vector<EquationDecl> out;
  out.reserve(eqs.size());
  for (const auto& e : eqs) {
    ArrayEvaluator ev(scope_, e.text, e.loc);
    if (ev.IsRecord(e.ast.lhs) || ev.IsRecord(e.ast.rhs)) {
      RecordEquation(&ev, e, &out);
      continue;
    }
    ArrayValue l = ev.Eval(e.ast.lhs), r = ev.Eval(e.ast.rhs);
    if (l.shape != r.shape) {
      ev.Fail(e.ast.rhs->column, "the two sides of the equation have different shapes: " +
                                     ShapeText(l.shape) + " and " + ShapeText(r.shape));
    }
    if (l.scalar()) {
      out.push_back(e);
      out.back().ast = {l.elements[0], r.elements[0]};
      continue;
    }
    for (size_t i = 0; i < l.elements.size(); ++i) {
      EquationDecl d = e;
      d.text = e.text + " (element " + SubscriptText(l.shape, i) + ")";
      d.ast = {l.elements[i], r.elements[i]};
      out.push_back(std::move(d));
    }
  }
  return out;
}

void DeclarationScalariser::RecordEquation(ArrayEvaluator* ev, const EquationDecl& e, std::vector<EquationDecl>* out) {
  ArrayEvaluator::RecordValue l = ev->EvalRecord(e.ast.lhs), r = ev->EvalRecord(e.ast.rhs);
  if (l.type != r.type) {
    ev->Fail(e.ast.rhs->column, "the two sides of the equation are different records: " + l.type->name + " and " + r.type->name);
  }
  // An overdetermined record's equation counts as its residues (docs/FORMAT.md, "Records").
  size_t counted = 0;
  for (size_t j = 0; j < l.type->fields.size(); ++j) {
    const ConnectorVariable& field = l.type->fields[j];
    for (size_t i = 0; i < l.fields[j].elements.size(); ++i) {
      EquationDecl d = e;
      d.text = e.text + " (" + field.name + (field.shape.empty() ? "" : "[" + SubscriptText(field.shape, i) + "]") + ")";
      d.ast = {l.fields[j].elements[i], r.fields[j].elements[i]};
      d.counted = e.counted && (l.type->residues == 0 || counted++ < static_cast<size_t>(l.type->residues));
      out->push_back(std::move(d));
    }
  }
}

std::vector<WhenDecl> DeclarationScalariser::Whens(const std::vector<WhenDecl>& whens) {
  std::vector<WhenDecl> out;
  for (const auto& w : whens) {
    WhenDecl d = w;
    d.condition = ArrayEvaluator(scope_, w.text, w.loc).Scalar(w.condition, "a when condition");
    d.statements.clear();
    for (const auto& statement : w.statements) {
      ArrayEvaluator ev(scope_, statement.text, statement.loc);
      ArrayValue target = ev.Eval(ParseName(statement.target, statement.loc));
      ArrayValue value = ev.Eval(statement.value);
      if (!value.scalar() && value.shape != target.shape) {
        ev.Fail(statement.value->column, "the value has shape " + ShapeText(value.shape) +
                                             ", but '" + statement.target + "' has shape " +
                                             ShapeText(target.shape));
      }
      for (size_t i = 0; i < target.elements.size(); ++i) {
        StatementDecl e = statement;
        e.target = target.elements[i]->PathText();
        e.value = value.scalar() ? value.elements[0] : value.elements[i];
        if (!target.scalar()) e.text += " (element " + SubscriptText(target.shape, i) + ")";
        d.statements.push_back(std::move(e));
      }
    }
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace momenta
