// momenta report, the 3-D scene: three.js (THREE, inlined before this script) draws the shapes of
// docs/FORMAT.md "Animation" as the MSL's Visualizers.Advanced.Shape places them. A shape's frame
// is at r (world) and turned by T, the transformation matrix from the world to the frame (MSL's
// R.T: v_frame = T v_world, so the frame's axes in the world are T's rows). In that frame the
// shape starts at r_shape and has the axes of Frames.from_nxy(length_direction, width_direction):
//   e_x = length_direction/|length_direction|, e_z = e_x × width_direction normalised,
//   e_y = e_z × e_x;
// it extends from 0 to length along e_x and is width wide along e_y, height high along e_z
// (centred on e_x). A sphere's diameter is length (width and height make it an ellipsoid); a
// cylinder, cone, pipe, gearwheel or spring has its axis along e_x.
//
// momentaScene3d(canvas, shapes, frames, value, palette) sets the scene up on `canvas` and returns
// the function that draws row i. The canvas carries data-scene="3d" and data-rendered (frames drawn
// so far); <body> data-scene-drawn the shapes drawn in the last frame.
function momentaScene3d(canvas, shapes, frames, value, palette) {
  "use strict";
  const kIdentity = [1, 0, 0, 0, 1, 0, 0, 0, 1];
  canvas.dataset.scene = "3d";
  canvas.dataset.rendered = 0;
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ canvas: canvas, antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    canvas.replaceWith(Object.assign(document.createElement("div"), {
      className: "plot-missing", textContent: "This browser cannot draw the 3-D scene (no WebGL): " + e.message,
    }));
    return () => {};
  }
  renderer.setPixelRatio(1);
  renderer.setSize(canvas.width, canvas.height, false);

  // ---- Small vector algebra on arrays ----------------------------------------------------------
  const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
  const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const norm = (a) => Math.sqrt(dot(a, a));
  // T' v: a vector given in the frame, in the world.
  const resolve1 = (T, v) => [T[0] * v[0] + T[3] * v[1] + T[6] * v[2],
                              T[1] * v[0] + T[4] * v[1] + T[7] * v[2],
                              T[2] * v[0] + T[5] * v[1] + T[8] * v[2]];
  // MSL Frames.TransformationMatrices.from_nxy: the rows e_x, e_y, e_z.
  function fromNxy(nx, ny) {
    const ex = norm(nx) < 1e-10 ? [1, 0, 0] : scale(nx, 1 / norm(nx));
    const ey = norm(ny) < 1e-10 ? [0, 1, 0] : scale(ny, 1 / norm(ny));
    const nz = cross(ex, ey);
    const nyAux = dot(nz, nz) > 1e-6 ? ey : Math.abs(ex[0]) > 1e-6 ? [0, 1, 0] : [1, 0, 0];
    const ezAux = cross(ex, nyAux);
    const ez = scale(ezAux, 1 / norm(ezAux));
    return [ex, cross(ez, ex), ez];
  }
  const finite = (a) => (Array.isArray(a) ? a.every((x) => x !== null && isFinite(x)) : a !== null && isFinite(a));

  // A field's value at row i, or `otherwise` when the shape does not give it.
  const get = (f, key, i, otherwise) => (f[key] ? value(f[key], i) : otherwise);

  // Where a solid is at row i: its origin, its unit axes in the world and its sizes.
  function place(f, i) {
    const r = value(f.r, i), T = get(f, "T", i, kIdentity);
    const length = value(f.length, i);
    const width = get(f, "width", i, length), height = get(f, "height", i, width);
    const axes = fromNxy(get(f, "length_direction", i, [1, 0, 0]), get(f, "width_direction", i, [0, 1, 0]));
    const values = [r, T, length, width, height].concat(axes);
    if (!values.every(finite)) return null;
    return {
      origin: add(r, resolve1(T, get(f, "r_shape", i, [0, 0, 0]))),
      axes: axes.map((e) => resolve1(T, e)),
      length: length, width: width, height: height, extra: get(f, "extra", i, 0),
    };
  }
  // The matrix taking the unit shape (x from 0 to 1, y and z from -1/2 to 1/2) to the world.
  function solidMatrix(p, sizes) {
    const [ax, ay, az] = p.axes.map((a, k) => scale(a, sizes[k]));
    return new THREE.Matrix4().set(ax[0], ay[0], az[0], p.origin[0],
                                   ax[1], ay[1], az[1], p.origin[1],
                                   ax[2], ay[2], az[2], p.origin[2],
                                   0, 0, 0, 1);
  }

  // ---- Unit geometries along x, made once (cones and pipes once per ratio) ----------------------
  const alongX = (g) => g.rotateZ(-Math.PI / 2);  // three's round shapes stand along y
  const unit = {
    sphere: new THREE.SphereGeometry(0.5, 32, 16).translate(0.5, 0, 0),
    box: new THREE.BoxGeometry(1, 1, 1).translate(0.5, 0, 0),
    cylinder: alongX(new THREE.CylinderGeometry(0.5, 0.5, 1, 32).translate(0, 0.5, 0)),
  };
  unit.beam = unit.box;
  unit.gearwheel = unit.cylinder;
  const byRatio = new Map();
  function ratioGeometry(kind, extra) {
    const ratio = Math.min(Math.max(Number(extra) || 0, 0), kind === "pipe" ? 0.999 : 1e3);
    const key = kind + ":" + ratio.toPrecision(3);
    if (!byRatio.has(key)) {
      // cone: the diameter at the end is `extra` times the one at the start; pipe: the inner
      // diameter is `extra` times the outer one.
      const g = kind === "cone"
        ? new THREE.CylinderGeometry(0.5 * ratio, 0.5, 1, 32).translate(0, 0.5, 0)
        : new THREE.LatheGeometry([0.5 * ratio, 0.5, 0.5, 0.5 * ratio, 0.5 * ratio].map(
            (x, k) => new THREE.Vector2(x, k === 2 || k === 3 ? 1 : 0)), 32);
      byRatio.set(key, alongX(g));
    }
    return byRatio.get(key);
  }
  // A coil of `windings` turns, its axis along x from 0 to length, coil diameter width, wire
  // diameter height/2 (MSL: height is twice the coil width), in metres.
  function springGeometry(p) {
    const turns = Math.max(1, Math.abs(p.extra) || 5), rc = p.width / 2, rw = Math.max(p.height / 4, 1e-6);
    const curve = new THREE.Curve();
    curve.getPoint = (s, out = new THREE.Vector3()) => {
      const a = 2 * Math.PI * turns * s;
      return out.set(s * p.length, rc * Math.cos(a), rc * Math.sin(a));
    };
    return new THREE.TubeGeometry(curve, Math.ceil(24 * turns), rw, 8, false);
  }

  // ---- The scene, lights and world axes --------------------------------------------------------
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xfcfcfa);
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  const owners = [...new Set(shapes.map((s) => s.owner))];
  const material = (s) => new THREE.MeshPhongMaterial({
    color: palette[owners.indexOf(s.owner) % palette.length], specular: 0x222222, shininess: 30,
    side: THREE.DoubleSide,
  });
  const colourOf = (s, object, i) => {
    if (!s.fields.color) return;
    const c = value(s.fields.color, i);
    if (finite(c)) object.material.color.setRGB(c[0] / 255, c[1] / 255, c[2] / 255, THREE.SRGBColorSpace);
  };

  // One three.js object a shape, and how it moves to row i (false: nothing to draw at i).
  const items = shapes.map((s) => {
    const f = s.fields;
    if (s.kind === "line3d") {
      const geometry = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]);
      const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: 0x333333 }));
      line.frustumCulled = false;
      return { object: line, points: (i) => [value(f.from, i), value(f.to, i)], update(i) {
        const [a, b] = this.points(i);
        if (!finite(a) || !finite(b)) return false;
        geometry.attributes.position.array.set(a.concat(b));
        geometry.attributes.position.needsUpdate = true;
        colourOf(s, line, i);
        return true;
      } };
    }
    if (s.kind === "frame") {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.Float32BufferAttribute(new Array(18).fill(0), 3));
      geometry.setAttribute("color", new THREE.Float32BufferAttribute([1, 0, 0, 1, 0, 0, 0, 0.6, 0, 0, 0.6, 0, 0, 0, 1, 0, 0, 1], 3));
      const lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ vertexColors: true }));
      lines.frustumCulled = false;
      const points = (i) => {
        const r = value(f.r, i), T = get(f, "T", i, kIdentity), length = value(f.length, i);
        return [r].concat([0, 1, 2].map((k) => add(r, scale(T.slice(3 * k, 3 * k + 3), length))));
      };
      return { object: lines, points: points, update(i) {
        const p = points(i);
        if (!p.every(finite)) return false;
        geometry.attributes.position.array.set([].concat(p[0], p[1], p[0], p[2], p[0], p[3]));
        geometry.attributes.position.needsUpdate = true;
        if (f.color) {  // one colour for the three axes
          const c = value(f.color, i);
          geometry.attributes.color.array.set(new Array(6).fill(c.map((x) => x / 255)).flat());
          geometry.attributes.color.needsUpdate = true;
        }
        return true;
      } };
    }
    // A solid.
    const mesh = new THREE.Mesh(unit[s.kind] || unit.box, material(s));
    mesh.matrixAutoUpdate = false;
    let springKey = "";
    return { object: mesh, points: (i) => {
      const p = place(f, i);
      if (!p) return [];
      const far = Math.max(Math.abs(p.width), Math.abs(p.height)) / 2;
      return [p.origin, add(p.origin, scale(p.axes[0], p.length))].map((q) => [q, far]);
    }, update(i) {
      const p = place(f, i);
      if (!p || p.length === 0) return false;
      if (s.kind === "spring") {
        const key = [p.length, p.width, p.height, p.extra].map((x) => x.toPrecision(4)).join();
        if (key !== springKey) {
          if (springKey) mesh.geometry.dispose();
          mesh.geometry = springGeometry(p);
          springKey = key;
        }
        mesh.matrix.copy(solidMatrix(p, [1, 1, 1]));
      } else {
        if (s.kind === "cone" || s.kind === "pipe") mesh.geometry = ratioGeometry(s.kind, p.extra);
        mesh.matrix.copy(solidMatrix(p, [p.length, p.width, p.height]));
      }
      mesh.matrixWorldNeedsUpdate = true;
      colourOf(s, mesh, i);
      return true;
    } };
  });
  for (const item of items) scene.add(item.object);

  // ---- The box every frame's shapes fit in (and the world's origin), for the camera ------------
  const lo = [0, 0, 0], hi = [0, 0, 0];
  const extend = (q, far) => {
    if (!finite(q)) return;
    for (let k = 0; k < 3; ++k) { lo[k] = Math.min(lo[k], q[k] - far); hi[k] = Math.max(hi[k], q[k] + far); }
  };
  for (let i = 0; i < frames; ++i) {
    for (const item of items) {
      for (const q of item.points(i)) {
        if (Array.isArray(q[0])) extend(q[0], q[1]); else extend(q, 0);
      }
    }
  }
  const centre = scale(add(lo, hi), 0.5);
  const radius = Math.max(norm([hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]]) / 2, 1e-3);
  const axes = new THREE.AxesHelper(0.25 * radius);
  scene.add(axes);

  // ---- Camera: it looks at the box's centre from `distance`, turned by `azimuth` about y and
  // raised by `elevation`; it opens looking along -z (x right, y up, as the MSL's default view).
  // Dragging turns it, the wheel moves it nearer or farther, a double click puts it back.
  const fov = 30;
  const camera = new THREE.PerspectiveCamera(fov, canvas.width / canvas.height, radius / 100, radius * 100);
  const home = { azimuth: 0, elevation: 0, distance: 1.1 * radius / Math.sin((fov / 2) * Math.PI / 180) };
  let view = Object.assign({}, home);
  function aim() {
    const ce = Math.cos(view.elevation), se = Math.sin(view.elevation);
    camera.position.set(centre[0] + view.distance * ce * Math.sin(view.azimuth), centre[1] + view.distance * se,
                        centre[2] + view.distance * ce * Math.cos(view.azimuth));
    camera.up.set(0, 1, 0);
    camera.lookAt(centre[0], centre[1], centre[2]);
    // The light comes from over the viewer's right shoulder.
    sun.position.copy(camera.position).add(new THREE.Vector3(radius, 2 * radius, 0));
    sun.target.position.set(centre[0], centre[1], centre[2]);
  }
  scene.add(sun, sun.target);
  let current = 0, rendered = 0;
  function draw(i) {
    current = i;
    let drawn = 0;
    for (const item of items) {
      item.object.visible = item.update(i);
      drawn += item.object.visible ? 1 : 0;
    }
    aim();
    renderer.render(scene, camera);
    canvas.dataset.rendered = ++rendered;
    document.body.dataset.sceneDrawn = drawn;
  }
  let drag = null;
  canvas.addEventListener("pointerdown", (e) => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener("pointerup", () => { drag = null; });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    view.azimuth -= (e.clientX - drag[0]) * 0.01;
    view.elevation = Math.max(-1.55, Math.min(1.55, view.elevation + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw(current);
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    view.distance *= Math.exp(0.001 * e.deltaY);
    draw(current);
  }, { passive: false });
  canvas.addEventListener("dblclick", () => { view = Object.assign({}, home); draw(current); });
  canvas.title = "drag to turn the view, wheel to zoom, double-click to reset";
  return draw;
}
