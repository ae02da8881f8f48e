// momenta report page: fills the page from the JSON in #momenta-data, draws the outputs with
// uPlot and animates the scene on a canvas (a 3-D scene through momentaScene3d, report/scene3d.js). When done it records what it drew as data-attributes
// of <body> (data-series, data-plots, data-scene-shapes, data-scene-frames, data-scene-drawn), which
// the test suite reads from headless Chromium.
(function () {
  "use strict";
  const data = JSON.parse(document.getElementById("momenta-data").textContent);
  const body = document.body;
  const palette = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2",
                   "#17becf", "#bcbd22", "#7f7f7f"];
  const column = {};  // column name -> index into data.data (0 is time)
  data.columns.forEach((name, k) => { column[name] = k + 1; });
  const time = data.data[0];

  function text(id, value) { document.getElementById(id).textContent = value; }
  function fmt(v) { return v === null ? "–" : Number(v.toPrecision(6)).toString(); }
  function row(table, cells, numeric) {
    const tr = table.insertRow();
    cells.forEach((c, k) => {
      const td = tr.insertCell();
      td.textContent = c;
      if (numeric && numeric[k]) td.className = "num";
    });
  }

  // ---- Header, notes and tables --------------------------------------------------------------
  text("model-name", data.model);
  document.title = data.model + " – momenta report";
  text("model-file", [data.file, data.result].filter((s) => s).join(" · "));
  text("model-doc", data.doc);
  const notes = document.getElementById("notes");
  for (const n of data.notes) { const li = document.createElement("li"); li.textContent = n; notes.appendChild(li); }
  const params = document.getElementById("parameters");
  row(params, ["name", "value", "unit", "description"]);
  for (const p of data.parameters) row(params, [p.name, fmt(p.value), p.unit, p.doc], [false, true]);
  for (const [label, value] of data.build) row(document.getElementById("build"), [label, value]);
  for (const [label, value] of data.solver) row(document.getElementById("solver"), [label, value]);

  // ---- Plots: the outputs by unit, at most eight to a chart -----------------------------------
  function eventLines(u) {
    const ctx = u.ctx;
    ctx.save();
    ctx.strokeStyle = "#888";
    ctx.setLineDash([5, 4]);
    ctx.lineWidth = 1;
    for (const t of data.events) {
      const x = Math.round(u.valToPos(t, "x", true));
      if (x < u.bbox.left || x > u.bbox.left + u.bbox.width) continue;
      ctx.beginPath();
      ctx.moveTo(x, u.bbox.top);
      ctx.lineTo(x, u.bbox.top + u.bbox.height);
      ctx.stroke();
    }
    ctx.restore();
  }
  let seriesDrawn = 0, plotsDrawn = 0;
  const plots = document.getElementById("plots");
  if (typeof uPlot === "undefined") {
    plots.innerHTML = '<div class="plot-missing">This momenta was built without uPlot (run scripts/setup.sh, ' +
                      "then rebuild), so the outputs are not plotted here; the tables and the scene are complete.</div>";
  } else {
    const groups = new Map();
    for (let k = 0; k < data.plotted; ++k) {
      const unit = data.units[k] || "";
      if (!groups.has(unit)) groups.set(unit, []);
      groups.get(unit).push(k);
    }
    const charts = [];
    for (const [unit, members] of groups) {
      for (let i = 0; i < members.length; i += 8) charts.push([unit, members.slice(i, i + 8)]);
    }
    const width = Math.min(plots.clientWidth || 960, 1000);
    charts.forEach(([unit, members], c) => {
      const div = document.createElement("div");
      plots.appendChild(div);
      const series = [{ label: "time [s]" }];
      const columns = [time];
      members.forEach((k, i) => {
        series.push({ label: data.columns[k] + (unit ? " [" + unit + "]" : ""), stroke: palette[i % palette.length],
                      width: 1.5, value: (u, v) => (v == null ? "–" : fmt(v)) });
        columns.push(data.data[k + 1]);
      });
      new uPlot({
        width: width, height: 300, series: series, scales: { x: { time: false } },
        axes: [{ label: "time [s]" }, { label: unit }],
        cursor: { drag: { x: true, y: false } },
        hooks: {
          draw: [eventLines],
          ready: [() => { plotsDrawn += 1; seriesDrawn += members.length;
                          body.dataset.plots = plotsDrawn; body.dataset.series = seriesDrawn; }],
        },
      }, columns, div);
    });
    if (charts.length === 0) { body.dataset.plots = 0; body.dataset.series = 0; }
  }

  // ---- Scene --------------------------------------------------------------------------------
  const shapes = data.scene;
  if (shapes.length === 0) return;
  document.getElementById("scene-section").hidden = false;
  const canvas = document.getElementById("scene");
  const frames = time.length;
  // A field's value at row i: a number, or its elements ([x, y]; a 3-vector; a 3x3 matrix row
  // by row).
  function value(field, i) {
    if (field.length === 1) return data.data[column[field[0]]][i];
    return field.map((name) => data.data[column[name]][i]);
  }
  let draw;
  if (!data.space) {
    draw = planarScene();
  } else if (typeof momentaScene3d === "function") {
    draw = momentaScene3d(canvas, shapes, frames, value, palette);
  } else {
    canvas.replaceWith(Object.assign(document.createElement("div"), {
      className: "plot-missing",
      textContent: "This momenta was built without three.js (run scripts/setup.sh, then rebuild), " +
                   "so the 3-D scene is not drawn here.",
    }));
    return;
  }

  // The planar scene on a 2-D canvas: returns the function that draws row i.
  function planarScene() {
    const ctx = canvas.getContext("2d");
    // The world box every frame's points (and circles) fit in.
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    function extend(p, r) {
      if (p[0] === null || p[1] === null) return;
      x0 = Math.min(x0, p[0] - r); x1 = Math.max(x1, p[0] + r);
      y0 = Math.min(y0, p[1] - r); y1 = Math.max(y1, p[1] + r);
    }
    for (let i = 0; i < frames; ++i) {
      for (const s of shapes) {
        const f = s.fields;
        if (f.at && s.kind !== "wall") extend(value(f.at, i), f.radius ? Math.abs(value(f.radius, i)) : 0);
        if (f.from) { extend(value(f.from, i), 0); extend(value(f.to, i), 0); }
        if (s.kind === "wall" && f.start && f.end && value(f.start, i) < value(f.end, i)) {
          const at = value(f.at, i), n = value(f.normal, i), len = Math.hypot(n[0], n[1]) || 1;
          const t = [n[1] / len, -n[0] / len];
          extend([at[0] + value(f.start, i) * t[0], at[1] + value(f.start, i) * t[1]], 0);
          extend([at[0] + value(f.end, i) * t[0], at[1] + value(f.end, i) * t[1]], 0);
        }
      }
    }
    if (!isFinite(x0)) { x0 = -1; x1 = 1; y0 = -1; y1 = 1; }
    const span = Math.max(x1 - x0, y1 - y0, 1e-6);
    const pad = 0.08 * span;
    x0 -= pad; x1 += pad; y0 -= pad; y1 += pad;
    const scale = Math.min(canvas.width / (x1 - x0), canvas.height / (y1 - y0));
    const ox = (canvas.width - scale * (x1 - x0)) / 2, oy = (canvas.height - scale * (y1 - y0)) / 2;
    const px = (p) => [ox + (p[0] - x0) * scale, canvas.height - oy - (p[1] - y0) * scale];
    const owners = [...new Set(shapes.map((s) => s.owner))];
    const colour = (s) => palette[owners.indexOf(s.owner) % palette.length];

    function hatch(p, dir, len) {  // short strokes on the side `dir` (a unit vector, screen axes)
      ctx.beginPath();
      const tx = -dir[1], ty = dir[0];
      for (let k = -len; k <= len; k += 6) {
        ctx.moveTo(p[0] + tx * k, p[1] + ty * k);
        ctx.lineTo(p[0] + tx * k + (dir[0] - tx) * 6, p[1] + ty * k + (dir[1] - ty) * 6);
      }
      ctx.stroke();
    }
    const paint = {
      circle(f, i, c) {
        const p = px(value(f.at, i)), r = Math.max(Math.abs(value(f.radius, i)) * scale, 4);
        ctx.fillStyle = c + "55"; ctx.strokeStyle = c; ctx.lineWidth = 2;
        ctx.beginPath(); ctx.arc(p[0], p[1], r, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
        if (f.angle) {
          const a = value(f.angle, i);
          ctx.beginPath(); ctx.moveTo(p[0], p[1]); ctx.lineTo(p[0] + r * Math.cos(a), p[1] - r * Math.sin(a)); ctx.stroke();
        }
      },
      line(f, i) {
        const a = px(value(f.from, i)), b = px(value(f.to, i));
        ctx.strokeStyle = "#333"; ctx.lineWidth = 3;
        ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
      },
      spring(f, i) {
        const a = px(value(f.from, i)), b = px(value(f.to, i));
        const dx = b[0] - a[0], dy = b[1] - a[1], len = Math.hypot(dx, dy) || 1;
        const nx = -dy / len * 6, ny = dx / len * 6;
        ctx.strokeStyle = "#555"; ctx.lineWidth = 1.5;
        ctx.beginPath(); ctx.moveTo(a[0], a[1]);
        for (let k = 1; k < 16; ++k) {
          const s = k / 16, side = k % 2 ? 1 : -1;
          ctx.lineTo(a[0] + dx * s + side * nx, a[1] + dy * s + side * ny);
        }
        ctx.lineTo(b[0], b[1]); ctx.stroke();
      },
      pin(f, i) {
        const p = px(value(f.at, i));
        ctx.fillStyle = "#fff"; ctx.strokeStyle = "#333"; ctx.lineWidth = 2;
        ctx.beginPath(); ctx.arc(p[0], p[1], 4, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      },
      ground(f, i) {
        const p = px(value(f.at, i));
        ctx.strokeStyle = "#333"; ctx.lineWidth = 2;
        ctx.beginPath(); ctx.moveTo(p[0] - 12, p[1]); ctx.lineTo(p[0] + 12, p[1]); ctx.stroke();
        ctx.lineWidth = 1; hatch([p[0], p[1]], [0, 1], 12);
      },
      wall(f, i) {
        const at = value(f.at, i), n = value(f.normal, i), len = Math.hypot(n[0], n[1]) || 1;
        const t = [n[1] / len, -n[0] / len];
        let s0 = f.start ? value(f.start, i) : 0, s1 = f.end ? value(f.end, i) : 0;
        if (!(s0 < s1)) { const far = 4 * (x1 - x0 + y1 - y0); s0 = -far; s1 = far; }
        const a = px([at[0] + s0 * t[0], at[1] + s0 * t[1]]), b = px([at[0] + s1 * t[0], at[1] + s1 * t[1]]);
        ctx.strokeStyle = "#333"; ctx.lineWidth = 2;
        ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
        // Hatches on the side away from the normal, along the drawn part.
        const dir = [-n[0] / len, n[1] / len], mid = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
        ctx.lineWidth = 1; hatch(mid, dir, Math.min(Math.hypot(b[0] - a[0], b[1] - a[1]) / 2, 2 * canvas.width));
      },
    };
    // Lines first, then masses, then pins on top.
    const order = { wall: 0, ground: 0, spring: 1, line: 2, circle: 3, pin: 4 };
    const sorted = shapes.slice().sort((a, b) => order[a.kind] - order[b.kind]);
    return function (i) {
      ctx.clearRect(0, 0, canvas.width, canvas.height);
      let drawn = 0;
      for (const s of sorted) {
        paint[s.kind](s.fields, i, colour(s));
        drawn += 1;
      }
      body.dataset.sceneDrawn = drawn;
    };
  }

  const scrub = document.getElementById("scrub");
  scrub.max = frames - 1;
  function render(i) {
    draw(i);
    scrub.value = i;
    text("scene-time", "t = " + time[i].toFixed(4) + " s");
  }
  body.dataset.sceneShapes = shapes.length;
  body.dataset.sceneFrames = frames;
  // The page opens at time 0, or at the time in its address: report.html#t=0.8.
  const start = /[#&]t=([0-9.eE+-]+)/.exec(location.hash);
  render(0);

  // ---- Playback: simulated time runs at `speed` times the wall clock ---------------------------
  let playing = false, simTime = time[0], last = 0, frame = 0;
  const play = document.getElementById("play"), speed = document.getElementById("speed");
  function frameAt(t) {  // the last row at or before t
    let lo = 0, hi = frames - 1;
    while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (time[mid] <= t) lo = mid; else hi = mid - 1; }
    return lo;
  }
  function tick(now) {
    if (!playing) return;
    simTime += (now - last) / 1000 * Number(speed.value);
    last = now;
    if (simTime >= time[frames - 1]) { simTime = time[frames - 1]; playing = false; play.textContent = "Play"; }
    frame = frameAt(simTime);
    render(frame);
    if (playing) requestAnimationFrame(tick);
  }
  play.addEventListener("click", () => {
    playing = !playing;
    play.textContent = playing ? "Pause" : "Play";
    if (playing) {
      if (frame >= frames - 1) { frame = 0; simTime = time[0]; }
      last = performance.now();
      requestAnimationFrame(tick);
    }
  });
  if (start) { frame = frameAt(Number(start[1])); simTime = time[frame]; render(frame); }
  scrub.addEventListener("input", () => { frame = Number(scrub.value); simTime = time[frame]; render(frame); });
})();
