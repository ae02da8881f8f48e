#include "app/report_scene.h"

#include <algorithm>
#include <set>

#include "core/lang/instance_scope.h"

namespace momenta {

namespace {

/// The number of elements of a field's value (1 for a scalar).
size_t ElementCount(const std::vector<int>& shape) {
  size_t n = 1;
  for (int d : shape) n *= static_cast<size_t>(d);
  return n;
}

/// The element names of an array output `base` of `shape`, as the array expansion writes them:
/// `base[1]`, or `base[1,1]` … row by row.
std::vector<std::string> ElementColumns(const std::string& base, const std::vector<int>& shape) {
  std::vector<std::string> out;
  if (shape.size() == 2) {
    for (int i = 1; i <= shape[0]; ++i) {
      for (int j = 1; j <= shape[1]; ++j) {
        out.push_back(base + "[" + std::to_string(i) + "," + std::to_string(j) + "]");
      }
    }
  } else {
    for (int i = 1; i <= shape[0]; ++i) out.push_back(base + "[" + std::to_string(i) + "]");
  }
  return out;
}

/// The parts of a field's expression recorded one output each: the elements of a list written
/// out with the field's shape (`[x, y, 0]`, a matrix as a list of rows), else the whole value.
std::vector<AstPtr> OutputParts(const AstPtr& expr, const std::vector<int>& shape) {
  auto is_list = [](const AstPtr& e, int n) {
    return e->kind == Ast::Kind::kArray && e->args.size() == static_cast<size_t>(n);
  };
  if (shape.empty() || !is_list(expr, shape[0])) return {expr};
  if (shape.size() == 1) return expr->args;
  std::vector<AstPtr> parts;
  for (const AstPtr& row : expr->args) {
    if (!is_list(row, shape[1])) return {expr};
    parts.insert(parts.end(), row->args.begin(), row->args.end());
  }
  return parts;
}

/// A vector or matrix named whole (`body.frame_a.r_0`) whose elements the model already outputs
/// one by one (`body.frame_a.r_0[1]` …): its elements, each one output, so that no element is
/// listed twice. Otherwise `parts` as they are.
std::vector<AstPtr> ElementsWhereListed(std::vector<AstPtr> parts, const std::vector<int>& shape,
                                        const std::set<std::string>& listed) {
  if (parts.size() != 1 || shape.empty() || parts[0]->kind != Ast::Kind::kName ||
      parts[0]->path.empty() || parts[0]->path.back().index) {
    return parts;
  }
  const std::vector<std::string> names = ElementColumns(AstToString(*parts[0]), shape);
  if (std::none_of(names.begin(), names.end(), [&](const std::string& n) { return listed.count(n) > 0; })) {
    return parts;
  }
  auto number = [](int k) {
    auto n = std::make_shared<Ast>();
    n->number = k;
    return AstPtr(n);
  };
  // `name[i]`, or `name[i, j]` row by row (j = 0: no second subscript).
  std::vector<AstPtr> elements;
  auto element = [&](int i, int j) {
    auto e = std::make_shared<Ast>(*parts[0]);
    e->path.back().index = number(i);
    if (j) e->path.back().index2 = number(j);
    elements.push_back(e);
  };
  for (int i = 1; i <= shape[0]; ++i) {
    if (shape.size() == 1) element(i, 0);
    for (int j = 1; shape.size() == 2 && j <= shape[1]; ++j) element(i, j);
  }
  return elements;
}

/// "a 3-D sphere" or "a planar circle", for the message about a mixed scene.
std::string Described(const ShapeDecl& decl) {
  return std::string(decl.space ? "a 3-D " : "a planar ") + decl.kind;
}

}  // namespace

Scene AddSceneOutputs(const FlatSystem& flat, ModelSpec* spec) {
  Scene scene;
  std::set<std::string> listed;
  for (const auto& o : spec->outputs) listed.insert(o.text);
  // The first shape sets the scene's kind: the model's shapes are all planar or all 3-D.
  const ShapeDecl* first = nullptr;
  std::string first_owner;
  for (uint32_t i = 0; i < flat.instances.size(); ++i) {
    const FlatInstance& inst = flat.instances[i];
    if (!inst.type || inst.type->animation.empty()) continue;
    // The instance's path as name segments (`R[3].body` -> R[3], body).
    const std::string inst_path = flat.InstancePath(InstanceId(i));
    for (const ShapeDecl& decl : inst.type->animation) {
      if (!first) {
        first = &decl;
        first_owner = inst_path;
        scene.space = decl.space;
      } else if (decl.space != scene.space) {
        throw ModelError(decl.loc, inst_path + " (" + inst.type->name + ") draws " +
                                       Described(decl) + ", but " + first_owner + " draws " +
                                       Described(*first) +
                                       ": a model's shapes are all planar or all 3-D");
      }
      SceneShape shape{decl.kind, inst_path, decl.space, {}};
      for (const ShapeField& f : decl.fields) {
        // A list written out is one scalar output an element (columns named after them);
        // anything else is one output, a vector's elements named by the array expansion.
        const AstPtr expr = InInstanceScope(f.expr, inst_path, inst.loc);
        SceneField field{f.key, {}, f.shape};
        for (const AstPtr& part : ElementsWhereListed(OutputParts(expr, f.shape), f.shape, listed)) {
          OutputSpec o;
          o.expr = part;
          o.text = AstToString(*part);
          o.loc = f.loc;
          if (listed.insert(o.text).second) {
            spec->outputs.push_back(o);
            scene.added.push_back(o.text);
          }
          field.columns.push_back(o.text);
        }
        shape.fields.push_back(std::move(field));
      }
      scene.shapes.push_back(std::move(shape));
    }
  }
  return scene;
}

size_t ResolveSceneColumns(const std::vector<std::string>& columns, Scene* scene) {
  const std::set<std::string> have(columns.begin(), columns.end());
  // The scene's own columns: each added text as a scalar or as the elements of a vector or a
  // 3x3 matrix.
  std::set<std::string> scene_only;
  for (const std::string& text : scene->added) {
    scene_only.insert(text);
    for (const std::string& base : {text, "(" + text + ")"}) {
      for (const std::vector<int>& shape : {std::vector<int>{3}, std::vector<int>{3, 3}}) {
        for (const std::string& name : ElementColumns(base, shape)) scene_only.insert(name);
      }
    }
  }
  scene->num_model_columns = 0;
  while (scene->num_model_columns < columns.size() &&
         !scene_only.count(columns[scene->num_model_columns])) {
    ++scene->num_model_columns;
  }
  auto kept = std::remove_if(scene->shapes.begin(), scene->shapes.end(), [&](SceneShape& shape) {
    for (SceneField& f : shape.fields) {
      // Scalars (one, or a list's elements) are their own columns; a vector's elements are
      // `name[1]`, or `(expr)[1]` for an expression (core/lang/arrays.cc), a matrix's `name[1,1]`.
      if (f.columns.size() == ElementCount(f.shape) &&
          std::all_of(f.columns.begin(), f.columns.end(),
                      [&](const std::string& c) { return have.count(c) > 0; })) {
        continue;
      }
      if (f.columns.size() != 1 || f.shape.empty()) return true;
      const std::string text = f.columns[0];
      bool found = false;
      for (const std::string& base : {text, "(" + text + ")"}) {
        std::vector<std::string> elements = ElementColumns(base, f.shape);
        if (std::all_of(elements.begin(), elements.end(),
                        [&](const std::string& c) { return have.count(c) > 0; })) {
          f.columns = std::move(elements);
          found = true;
          break;
        }
      }
      if (!found) return true;
    }
    return false;
  });
  const size_t dropped = scene->shapes.end() - kept;
  scene->shapes.erase(kept, scene->shapes.end());
  return dropped;
}

}  // namespace momenta
