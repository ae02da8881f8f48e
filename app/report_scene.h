#pragma once
/// The report's scene: what the component types' `animation:` declarations (docs/FORMAT.md,
/// "Animation") ask to draw for a model's instances, recorded as extra output columns.

#include <string>
#include <vector>

#include "core/compile/compiled_model.h"
#include "core/lang/model_spec.h"

namespace momenta {

/// One value of a drawn shape, named by the output column(s) that hold it: one for a scalar
/// (radius, angle), two for a planar point or direction (x then y), three for a 3-vector, nine
/// for a 3x3 matrix (row by row). `shape` is the value's ([], [2], [3] or [3, 3]).
struct SceneField {
  std::string key;
  std::vector<std::string> columns;
  std::vector<int> shape;
};

/// A shape drawn for one instance: its kind (circle, line, spring, pin, ground, wall; sphere,
/// box, cylinder, cone, pipe, beam, gearwheel, spring, frame, line3d) and fields.
struct SceneShape {
  std::string kind, owner;
  bool space = false;  ///< a 3-D shape
  std::vector<SceneField> fields;
};

struct Scene {
  std::vector<SceneShape> shapes;
  std::vector<std::string> added;  ///< output texts added for the scene alone
  /// After ResolveSceneColumns: the leading columns that are the model's own outputs; the
  /// columns after them are the scene's alone.
  size_t num_model_columns = 0;
  bool space = false;  ///< a 3-D scene (every shape is 3-D)
  bool empty() const { return shapes.empty(); }
};

/// Finds every instance of the flattened model `flat` whose type declares an animation and
/// appends to spec->outputs the expressions its shapes need, in the model's scope (`A.r`,
/// `[cord.frame_a.x, cord.frame_a.y]`, `b.T`); an expression the model already outputs is not
/// added again. A list written out (`[x, y, 0]`) is one output an element. Throws ModelError at
/// a shape's line when the model's shapes are not all planar or all 3-D. Returns the scene with the output texts each field reads; ResolveSceneColumns turns
/// them into column names once the model is built. The build calls it (BuildOptions::add_outputs)
/// and flattens the model again with these outputs, reporting a name a field lacks as Flatten
/// does.
Scene AddSceneOutputs(const FlatSystem& flat, ModelSpec* spec);

/// Replaces each field's output text by the built model's column names for it (a vector output
/// `A.r` is the columns `A.r[1]`, `A.r[2]`, a matrix `b.T` is `b.T[1,1]` … `b.T[3,3]`); a field whose columns are missing from `columns`
/// drops its shape; sets num_model_columns. Returns the number of shapes dropped.
size_t ResolveSceneColumns(const std::vector<std::string>& columns, Scene* scene);

}  // namespace momenta
