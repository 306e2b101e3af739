// For the end-to-end tests: with `#probe=T1,T2,...` in the address, the page seeks to each
// time as the scrubber does, reads back what it shows (module positions, highlight, state
// panel, markers, pixels of each part's colour on the canvas) and what it loaded, and writes
// it as JSON into <pre id="probe">, where a headless browser's DOM dump finds it.

// Pixels of each of `colours` ([r, g, b], by part), shaded or not.
function colourCounts(canvas, colours) {
  const copy = document.createElement('canvas');
  copy.width = canvas.width;
  copy.height = canvas.height;
  const g = copy.getContext('2d');
  g.drawImage(canvas, 0, 0);
  const data = g.getImageData(0, 0, copy.width, copy.height).data;
  const near = (r, g2, b, c) => {
    const [cr, cg, cb] = c;
    // Shading scales a colour: compare the direction of the colour vectors.
    const dot = r * cr + g2 * cg + b * cb;
    const n = Math.hypot(r, g2, b) * Math.hypot(cr, cg, cb);
    return n > 0 && dot / n > 0.985 && Math.hypot(r, g2, b) > 60;
  };
  const parts = colours.map(() => 0);
  for (let i = 0; i < data.length; i += 4) {
    const k = colours.findIndex((c) => near(data[i], data[i + 1], data[i + 2], c));
    if (k >= 0) parts[k]++;
  }
  return { parts, pixels: data.length / 4 };
}

// `#bench=K`: the cost of K frames (seek through the run, draw, wait for the GPU) in ms.
function frameCost(viewer, frames) {
  const gl = viewer.scene.renderer.getContext();
  const start = performance.now();
  for (let k = 0; k < frames; k++) {
    viewer.seek((viewer.rec.end_ms * k) / frames);
    gl.finish();
  }
  return (performance.now() - start) / frames;
}

export function runProbe(viewer, readyMs) {
  const match = /probe=([0-9.,]+)/.exec(window.location.hash);
  if (!match) return;
  const bench = /bench=([0-9]+)/.exec(window.location.hash);
  const violations = [];
  document.addEventListener('securitypolicyviolation', (e) => violations.push(e.blockedURI));
  const samples = match[1]
    .split(',')
    .filter((x) => x !== '')
    .map((t) => {
      viewer.seek(Number(t));
      return viewer.probe();
    });
  const result = {
    samples,
    colours: colourCounts(
      viewer.scene.renderer.domElement,
      viewer.rec.drawing.parts.map((p) => p.colour),
    ),
    resources: performance.getEntriesByType('resource').map((r) => r.name),
    violations,
    legend: viewer.legend.shown(),
    modules: viewer.rec.modules.length,
    ready_ms: readyMs,
    frame_ms: bench ? frameCost(viewer, Number(bench[1])) : null,
  };
  const out = document.createElement('pre');
  out.id = 'probe';
  out.textContent = JSON.stringify(result);
  document.body.appendChild(out);
}
