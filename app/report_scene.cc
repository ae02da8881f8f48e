#include "app/report_scene.h"

#include <algorithm>
#include <set>

#include "core/lang/instance_scope.h"

namespace momenta {

Scene AddSceneOutputs(const FlatSystem& flat, ModelSpec* spec) {
  Scene scene;
  std::set<std::string> listed;
  for (const auto& o : spec->outputs) listed.insert(o.text);
  for (uint32_t i = 0; i < flat.instances.size(); ++i) {
    const FlatInstance& inst = flat.instances[i];
    if (!inst.type || inst.type->animation.empty()) continue;
    // The instance's path as name segments (`R[3].body` -> R[3], body).
    const std::string inst_path = flat.InstancePath(InstanceId(i));
    for (const ShapeDecl& decl : inst.type->animation) {
      SceneShape shape{decl.kind, inst_path, {}};
      for (const ShapeField& f : decl.fields) {
        // A point written as [x, y] is two scalar outputs (columns named after them); anything
        // else is one output, a vector's elements named by the array expansion.
        const AstPtr expr = InInstanceScope(f.expr, inst_path, inst.loc);
        std::vector<AstPtr> parts = {expr};
        if (expr->kind == Ast::Kind::kArray && expr->args.size() == 2) parts = expr->args;
        SceneField field{f.key, {}};
        for (const AstPtr& part : parts) {
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
  // The scene's own columns: each added text as a scalar or as the elements of a vector.
  std::set<std::string> scene_only;
  for (const std::string& text : scene->added) {
    for (const std::string& name :
         {text, text + "[1]", text + "[2]", "(" + text + ")[1]", "(" + text + ")[2]"}) {
      scene_only.insert(name);
    }
  }
  scene->num_model_columns = 0;
  while (scene->num_model_columns < columns.size() &&
         !scene_only.count(columns[scene->num_model_columns])) {
    ++scene->num_model_columns;
  }
  auto kept = std::remove_if(scene->shapes.begin(), scene->shapes.end(), [&](SceneShape& shape) {
    for (SceneField& f : shape.fields) {
      // Scalars (one, or a point's two) are their own columns; a vector's elements are
      // `name[1]`, or `(expr)[1]` for an expression (core/lang/arrays.cc).
      if (std::all_of(f.columns.begin(), f.columns.end(),
                      [&](const std::string& c) { return have.count(c) > 0; })) {
        continue;
      }
      if (f.columns.size() != 1) return true;
      const std::string text = f.columns[0];
      bool found = false;
      for (const std::string& base : {text, "(" + text + ")"}) {
        if (have.count(base + "[1]") && have.count(base + "[2]")) {
          f.columns = {base + "[1]", base + "[2]"};
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
