// thicket explore: the page. Everything it shows comes from the server's JSON (docs/explore.md);
// three.js (Debian's libjs-three, r111) draws the mesh, the nodes and the recorded ray.
'use strict';

const $ = (id) => document.getElementById(id);
const state = { scene: null, stats: null, trace: null, step: -1, timer: null, view: null, pending: new Set(),
  nodesAsked: 0, drawn: null, heat: null, pixel: null };

// What a test (tests/explore/browser_test.py, over the DevTools protocol) reads of the page: the
// structure and depth drawn with the counts of what the 3D view holds, the heatmap's request and
// hottest pixels, the traced pixel, its ray and steps; settled() resolves once no request is pending.
window.thicketExplore = {
  state: state,
  settled: async () => {
    while (state.pending.size) await Promise.allSettled([...state.pending]);
    return true;
  },
  // Where the drawn view shows world point p: page coordinates in CSS pixels, through the camera
  // three.js draws with (the browser test checks that a traced ray runs under the mouse).
  project: (p) => {
    const r = $('gl').getBoundingClientRect();
    const v = new THREE.Vector3(p[0], p[1], p[2]).project(three.camera);
    return [r.left + (v.x + 1) / 2 * r.width, r.top + (1 - v.y) / 2 * r.height];
  },
};
/// Keeps `promise` among the pending work until it settles, and returns it.
function track(promise) {
  state.pending.add(promise);
  const done = () => state.pending.delete(promise);
  promise.then(done, done);
  return promise;
}

function status(text) { $('status').textContent = text; }
// Script errors are kept on the page, where the browser test reads them.
window.addEventListener('error', (e) => {
  document.body.dataset.errors = (document.body.dataset.errors || '') + e.message + '; ';
});

/// The JSON of a request, or an Error carrying the server's message.
async function api(path, body) {
  const init = body === undefined ? {} : { method: 'POST', body: JSON.stringify(body) };
  const res = await fetch(path, init);
  const json = await res.json();
  if (!res.ok) throw new Error(path + ': ' + (json.error || res.status));
  return json;
}

// ---- 3D view: renderer, orbit camera, layers -------------------------------------------------
const three = { ok: typeof THREE !== 'undefined' };
function setupThree() {
  if (!three.ok) { status('three.js did not load: install libjs-three (scripts/setup)'); return; }
  try {
    three.renderer = new THREE.WebGLRenderer({ canvas: $('gl'), antialias: true });
  } catch (e) {
    three.ok = false;
    document.body.dataset.webgl = 'unavailable';
    status('WebGL unavailable (' + e.message + '): the panels still work');
    return;
  }
  document.body.dataset.webgl = 'ok';
  three.scene = new THREE.Scene();
  three.scene.background = new THREE.Color(0x303236);
  three.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
  three.scene.add(new THREE.HemisphereLight(0xffffff, 0x444444, 1.0));
  const sun = new THREE.DirectionalLight(0xffffff, 0.5);
  sun.position.set(1, 2, 1.5);
  three.scene.add(sun);
  three.nodes = new THREE.Group();
  three.trace = new THREE.Group();
  three.scene.add(three.nodes, three.trace);
}

// The orbit: the camera looks at `target` from `radius` away, at angles theta (around y) and phi.
const orbit = { target: [0, 0, 0], radius: 1, theta: 0.6, phi: 1.2 };
function cameraJson() {
  const s = Math.sin(orbit.phi), t = orbit.target;
  const eye = [t[0] + orbit.radius * s * Math.sin(orbit.theta), t[1] + orbit.radius * Math.cos(orbit.phi),
               t[2] + orbit.radius * s * Math.cos(orbit.theta)];
  return { eye: eye, target: t.slice(), up: [0, 1, 0], fov: 45 };
}
function render() {
  const canvas = $('gl');
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (!three.ok || w === 0 || h === 0) return;
  three.renderer.setSize(w, h, false);
  three.camera.aspect = w / h;
  const c = cameraJson();
  three.camera.position.set(c.eye[0], c.eye[1], c.eye[2]);
  three.camera.up.set(0, 1, 0);
  three.camera.lookAt(c.target[0], c.target[1], c.target[2]);
  three.camera.near = orbit.radius * 0.001;
  three.camera.far = orbit.radius * 100;
  three.camera.updateProjectionMatrix();
  three.renderer.render(three.scene, three.camera);
}
function setupOrbit() {
  const canvas = $('gl');
  let drag = null;
  canvas.addEventListener('mousedown', (e) => { drag = { x: e.clientX, y: e.clientY, moved: false }; });
  window.addEventListener('mousemove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
    orbit.theta -= dx * 0.01;
    orbit.phi = Math.min(3.1, Math.max(0.05, orbit.phi - dy * 0.01));
    drag.x = e.clientX; drag.y = e.clientY;
    render();
  });
  window.addEventListener('mouseup', (e) => {
    if (drag && !drag.moved && e.target === canvas) tracePixelAt(e);
    drag = null;
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    orbit.radius *= Math.exp(e.deltaY * 0.001);
    render();
  }, { passive: false });
  window.addEventListener('resize', render);
}

/// Line segments from a flat list of corner pairs [[a, b], ...].
function segments(pairs, color) {
  const p = new Float32Array(pairs.length * 6);
  let k = 0;
  for (const [a, b] of pairs) for (const v of a.concat(b)) p[k++] = v;
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(p, 3));
  return new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: color }));
}
const kBoxEdges = [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]];
/// Line segments of the 12 edges of each box [minx, miny, minz, maxx, maxy, maxz].
function boxLines(boxes, color) {
  const pairs = [];
  for (const b of boxes) {
    const c = (i) => [(i & 1) ? b[3] : b[0], (i & 2) ? b[4] : b[1], (i & 4) ? b[5] : b[2]];
    for (const [i, j] of kBoxEdges) pairs.push([c(i), c(j)]);
  }
  return segments(pairs, color);
}
/// The 12 edges of each oriented box {center, axes: three half-axes}.
function orientedLines(obbs, color) {
  const pairs = [];
  for (const o of obbs) {
    const c = (i) => [0, 1, 2].map((k) => o.center[k] + [0, 1, 2].reduce((s, a) =>
      s + ((i >> a) & 1 ? 1 : -1) * o.axes[a][k], 0));
    for (const [i, j] of kBoxEdges) pairs.push([c(i), c(j)]);
  }
  return segments(pairs, color);
}
/// The 6 edges of each tetrahedron {corners: four points}.
function tetraLines(tets, color) {
  const pairs = [];
  for (const t of tets) for (const [i, j] of [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]) pairs.push([t.corners[i], t.corners[j]]);
  return segments(pairs, color);
}
/// Split planes {polygon: convex corners} as translucent faces (fans) with their outlines.
function planeMeshes(planes, color) {
  const tris = [], pairs = [];
  let polygons = 0;
  for (const pl of planes) {
    const q = pl.polygon;
    if (q.length >= 3) polygons++;
    for (let i = 1; i + 1 < q.length; i++) tris.push(...q[0], ...q[i], ...q[i + 1]);
    for (let i = 0; i < q.length; i++) pairs.push([q[i], q[(i + 1) % q.length]]);
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(tris), 3));
  const faces = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ color: color, transparent: true, opacity: 0.22,
    side: THREE.DoubleSide, depthWrite: false }));
  faces.userData.polygons = polygons;
  return [faces, segments(pairs, color)];
}
function clearGroup(g) {
  while (g.children.length) {
    const o = g.children.pop();
    o.geometry.dispose();
    o.material.dispose();
  }
}

// ---- loading: scene, mesh, stats ---------------------------------------------------------------
async function loadScene() {
  const s = await api('/api/scene');
  state.scene = s;
  $('scene-line').textContent = s.name + ': ' + s.triangles + ' triangles' + (s.shapes ? ', ' + s.shapes + ' shapes' : '');
  $('display-line').textContent = s.display.stride > 1
    ? 'shown: every ' + s.display.stride + 'th triangle (' + s.display.triangles + '), above ' + s.display.limit
    : 'every triangle shown';
  for (const sel of [$('structure'), $('structure-b')]) {
    s.structures.forEach((st, i) => {
      const o = document.createElement('option');
      o.value = String(i);
      o.textContent = st.spec + (st.draws_nodes ? '' : ' (not drawn)');
      sel.appendChild(o);
    });
  }
  if (s.bounds) {
    const b = s.bounds;
    orbit.target = [(b[0] + b[3]) / 2, (b[1] + b[4]) / 2, (b[2] + b[5]) / 2];
    orbit.radius = 1.8 * Math.hypot(b[3] - b[0], b[4] - b[1], b[5] - b[2]) || 1;
  }
  document.body.dataset.scene = s.name;
}
async function loadMesh() {
  const res = await fetch('/api/mesh');
  const bytes = await res.arrayBuffer();
  const positions = new Float32Array(bytes);
  document.body.dataset.meshTriangles = String(positions.length / 9);
  if (!three.ok) return;
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  g.computeVertexNormals();
  const m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ color: 0xb8b0a0, side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 }));
  three.scene.add(m);
}
function fmtBytes(n) {
  const u = ['B', 'KiB', 'MiB', 'GiB'];
  let i = 0;
  while (n >= 1024 && i < 3) { n /= 1024; i++; }
  return n.toFixed(i ? 1 : 0) + ' ' + u[i];
}
async function loadStats() {
  const s = await api('/api/stats');
  state.stats = s;
  const rows = [['structure', (x) => x.spec], ['primitives', (x) => x.primitives], ['nodes', (x) => x.nodes],
    ['leaves', (x) => x.leaves], ['max depth', (x) => x.max_depth], ['structure memory', (x) => fmtBytes(x.bytes)],
    ['primitive memory', (x) => fmtBytes(x.primitive_bytes)],
    ['SAH cost', (x) => x.sah_cost === null ? 'undefined' : x.sah_cost.toFixed(3)],
    ['build time', (x) => x.build_ms.toFixed(1) + ' ms']];
  const keys = [];
  for (const x of s.structures) for (const k of Object.keys(x.extra)) if (!keys.includes(k)) keys.push(k);
  for (const k of keys) rows.push([k, (x) => x.extra[k] || '']);
  const table = document.createElement('table');
  table.id = 'stats-table';
  for (const [name, f] of rows) {
    const tr = table.insertRow();
    const th = document.createElement('th');
    th.textContent = name;
    tr.appendChild(th);
    for (const x of s.structures) tr.insertCell().textContent = String(f(x));
  }
  $('stats').replaceChildren(table);
}

// ---- the structure at one depth, drawn in its own terms ---------------------------------------
async function showNodes() {
  const structure = Number($('structure').value || 0);
  const depth = Number($('depth').value);
  $('depth-label').textContent = String(depth);
  const st = state.scene.structures[structure];
  // A slider moved quickly asks several depths at once: only the last asked is drawn.
  const asked = ++state.nodesAsked;
  const r = st.draws_nodes ? await api('/api/nodes', { structure: structure, depth: depth }) : null;
  if (asked !== state.nodesAsked) return;
  if (three.ok) clearGroup(three.nodes);
  for (const k of ['boxes', 'planes', 'oriented', 'tetrahedra']) document.body.dataset[k] = '0';
  state.drawn = { structure: structure, depth: depth, drawing: 'none', boxes: 0, planes: 0, oriented: 0, tetrahedra: 0 };
  if (!st.draws_nodes) {
    $('nodes-line').textContent = st.spec + ' does not draw its nodes';
    document.body.dataset.drawing = 'none';
    render();
    return;
  }
  $('depth').max = String(r.max_depth);
  // A structure with fewer levels clamps the slider: draw the depth it now shows.
  if (Number($('depth').value) !== depth) return showNodes();
  $('nodes-line').textContent = r.drawing + ': ' + r.count + ' at depth ' + depth + ' of ' + r.max_depth +
    (r.truncated ? ' (every ' + r.stride + 'th drawn: ' + r.drawn + ', the limit is ' + r.limit + ')' : '');
  $('depth-means').textContent = 'depth: ' + r.depth_means;
  const body = document.body.dataset;
  body.drawing = r.drawing;
  if (three.ok) {
    // What the 3D view holds, counted from its geometry (the browser test reads these): line
    // segments per box (12) or tetrahedron (6), and the polygons the plane faces were made of.
    const lines = (o, per) => String(o.geometry.attributes.position.count / 2 / per);
    // Among planes the boxes are the leaves' cells: drawn dimmer, so the planes stand out.
    if (r.boxes.length) {
      const o = boxLines(r.boxes.map((b) => b.box), r.planes.length ? 0x3a6f9f : 0x4fa3ff);
      three.nodes.add(o);
      body.boxes = lines(o, 12);
    }
    if (r.planes.length) {
      const [faces, outline] = planeMeshes(r.planes, 0xff9040);
      three.nodes.add(faces, outline);
      body.planes = String(faces.userData.polygons);
    }
    if (r.oriented.length) {
      const o = orientedLines(r.oriented, 0x60e0a0);
      three.nodes.add(o);
      body.oriented = lines(o, 12);
    }
    if (r.tetrahedra.length) {
      const o = tetraLines(r.tetrahedra, 0xd080ff);
      three.nodes.add(o);
      body.tetrahedra = lines(o, 6);
    }
  }
  state.drawn.drawing = r.drawing;
  for (const k of ['boxes', 'planes', 'oriented', 'tetrahedra']) state.drawn[k] = Number(body[k]);
  render();
}

// ---- heatmap -----------------------------------------------------------------------------------
/// The heatmap image: at most 256 pixels wide, the view's aspect.
function imageSize() {
  const c = $('gl');
  const aspect = (c.clientWidth || 4) / (c.clientHeight || 3);
  const width = Math.max(8, Math.min(256, Math.round(c.clientWidth / 3) || 160));
  return { width: width, height: Math.max(8, Math.min(512, Math.round(width / aspect))) };
}
function heatColor(v) {  // 0..1 → black, red, yellow, white
  const r = Math.min(1, v * 3), g = Math.min(1, Math.max(0, v * 3 - 1)), b = Math.min(1, Math.max(0, v * 3 - 2));
  return [r * 255, g * 255, b * 255];
}
function drawHeat(canvas, map, width, height, max) {
  canvas.width = width;
  canvas.height = height;
  const ctx = canvas.getContext('2d');
  const img = ctx.createImageData(width, height);
  for (let i = 0; i < map.values.length; i++) {
    const c = heatColor(max ? map.values[i] / max : 0);
    img.data.set([c[0], c[1], c[2], 255], 4 * i);
  }
  ctx.putImageData(img, 0, 0);
}
async function heatmap() {
  const size = imageSize();
  const structures = [Number($('structure').value || 0)];
  if ($('structure-b').value !== '') structures.push(Number($('structure-b').value));
  const body = { structures: structures, camera: cameraJson(), width: size.width, height: size.height,
    metric: $('metric').value };
  const r = await api('/api/heatmap', body);
  const box = $('heatmaps');
  box.replaceChildren();
  state.heat = { request: body, hottest: [] };
  r.maps.forEach((m, i) => {
    const fig = document.createElement('figure');
    const c = document.createElement('canvas');
    drawHeat(c, m, r.width, r.height, r.max);
    // The page's own reading of the values: the pixel with the most work (first on ties).
    let hot = 0;
    for (let k = 1; k < m.values.length; k++) if (m.values[k] > m.values[hot]) hot = k;
    const cap = document.createElement('figcaption');
    cap.id = 'heat-caption-' + i;
    cap.dataset.hottest = (hot % r.width) + ',' + Math.floor(hot / r.width);
    state.heat.hottest.push([hot % r.width, Math.floor(hot / r.width)]);
    cap.textContent = m.structure + ': total ' + m.total + ', max ' + m.max + ' at (' + cap.dataset.hottest + ')';
    fig.append(c, cap);
    box.appendChild(fig);
    if (i === 0) drawHeat($('overlay'), m, r.width, r.height, r.max);
  });
  const scale = document.createElement('p');
  scale.textContent = 'one scale: black 0 → white ' + r.max + ' ' + (r.metric === 'nodes' ? 'nodes' : 'primitive tests');
  box.appendChild(scale);
  $('overlay').style.display = $('overlay-on').checked ? '' : 'none';
  state.view = body;
  document.body.dataset.heatRequest = JSON.stringify(body);  // the browser test asks the server again
  document.body.dataset.heatmap = String(r.maps.length);
}

// ---- one ray's traversal -------------------------------------------------------------------------
async function tracePixel(x, y, size) {
  const structure = Number($('structure').value || 0);
  const camera = cameraJson();
  const r = await api('/api/trace', { structure: structure, camera: camera, width: size.width,
    height: size.height, x: x, y: y });
  state.trace = r;
  state.pixel = { x: x, y: y, width: size.width, height: size.height, structure: structure, camera: camera };
  $('trace-line').textContent = r.structure + ', pixel (' + x + ', ' + y + '): ' + r.nodes + ' nodes, ' + r.prims +
    ' primitive tests, ' + (r.hit ? 'hit primitive ' + r.hit.prim + ' at t = ' + r.hit.t.toPrecision(6) : 'no hit') +
    (r.detailed ? '' : ' (this structure reports only the totals)') + (r.dropped ? ', ' + r.dropped + ' steps not listed' : '');
  const list = $('steps');
  list.replaceChildren();
  r.steps.forEach((s, i) => {
    const li = document.createElement('li');
    li.className = s.kind;
    li.textContent = s.kind + ' ' + (s.kind === 'prim' ? 'primitive ' : s.tetrahedron ? 'tetrahedron ' : 'node ') + s.id +
      (s.t === null ? '' : ' t=' + s.t.toPrecision(5));
    li.addEventListener('click', () => showStep(i));
    list.appendChild(li);
  });
  document.body.dataset.traceSteps = String(r.steps.length);
  document.body.dataset.traceRay = r.ray.org.concat(r.ray.dir).join(',');
  showStep(-1);
}
function tracePixelAt(e) {
  const rect = $('gl').getBoundingClientRect();
  const size = imageSize();
  const x = Math.min(size.width - 1, Math.floor((e.clientX - rect.left) / rect.width * size.width));
  const y = Math.min(size.height - 1, Math.floor((e.clientY - rect.top) / rect.height * size.height));
  track(tracePixel(x, y, size)).catch((err) => status(err.message));
}
/// Shows steps 0..i: the current node's box (green entered, red culled, grey skipped) or tested triangle, and the ray.
function showStep(i) {
  const r = state.trace;
  if (!r) return;
  state.step = Math.max(-1, Math.min(r.steps.length - 1, i));
  const items = $('steps').children;
  for (let k = 0; k < items.length; k++) items[k].classList.toggle('current', k === state.step);
  if (state.step >= 0) items[state.step].scrollIntoView({ block: 'nearest' });
  const s = r.steps[state.step];
  $('step-line').textContent = s ? 'step ' + (state.step + 1) + ' of ' + r.steps.length + ': ' + s.kind + ' ' + s.id
    : r.steps.length + ' steps: press next or play';
  if (!three.ok) return;
  clearGroup(three.trace);
  const o = r.ray.org, d = r.ray.dir;
  const far = r.hit ? r.hit.t : orbit.radius * 2;
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(o.concat([o[0] + d[0] * far, o[1] + d[1] * far,
    o[2] + d[2] * far])), 3));
  three.trace.add(new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0xffff00 })));
  if (s && s.box) three.trace.add(boxLines([s.box], s.kind === 'enter' ? 0x40ff60 : s.kind === 'skip' ? 0x9090a0 : 0xff4040));
  // A tetrahedral walk: the tetrahedra entered so far (violet), the current one green.
  const walked = r.steps.slice(0, state.step).filter((w) => w.tetrahedron).map((w) => ({ corners: w.tetrahedron }));
  if (walked.length) three.trace.add(tetraLines(walked, 0xb070e0));
  if (s && s.tetrahedron) three.trace.add(tetraLines([{ corners: s.tetrahedron }], 0x40ff60));
  if (s && s.triangle) {
    const tg = new THREE.BufferGeometry();
    tg.setAttribute('position', new THREE.BufferAttribute(new Float32Array(s.triangle.flat()), 3));
    three.trace.add(new THREE.Mesh(tg, new THREE.MeshBasicMaterial({ color: 0xffd000, side: THREE.DoubleSide })));
  }
  render();
}
function play() {
  if (state.timer) { clearInterval(state.timer); state.timer = null; $('play').textContent = '▶ play'; return; }
  $('play').textContent = '■ stop';
  state.timer = setInterval(() => {
    if (!state.trace || state.step + 1 >= state.trace.steps.length) return play();
    showStep(state.step + 1);
  }, 300);
}

// ---- start -------------------------------------------------------------------------------------
function report(promise) { return track(promise).catch((e) => { status(e.message); throw e; }); }
async function main() {
  setupThree();
  setupOrbit();
  await report(loadScene());
  await Promise.all([report(loadMesh()), report(loadStats())]);
  $('structure').addEventListener('change', () => report(showNodes()));
  $('depth').addEventListener('input', () => report(showNodes()));
  $('heatmap-button').addEventListener('click', () => report(heatmap()));
  $('overlay-on').addEventListener('change', () => { $('overlay').style.display = $('overlay-on').checked ? '' : 'none'; });
  // Hiding the structure leaves a ray's walk alone in the view (a tetrahedral mesh hides it otherwise).
  $('nodes-on').addEventListener('change', () => {
    if (three.ok) three.nodes.visible = $('nodes-on').checked;
    render();
  });
  $('prev').addEventListener('click', () => showStep(state.step - 1));
  $('next').addEventListener('click', () => showStep(state.step + 1));
  $('play').addEventListener('click', play);
  const params = new URLSearchParams(location.search);
  if (params.has('depth')) {  // before the first answer gives the true maximum
    $('depth').max = '1000';
    $('depth').value = params.get('depth');
  }
  await report(showNodes());
  // ?structure=S (an index or a spec): switch to it once the first structure is drawn, as a
  // reader choosing it would, keeping ?depth.
  if (params.has('structure')) {
    const want = params.get('structure');
    const i = state.scene.structures.findIndex((st, k) => String(k) === want || st.spec === want);
    if (i < 0) throw new Error('?structure=' + want + ': no such structure on this server');
    $('structure').value = String(i);
    if (params.has('depth')) { $('depth').max = '1000'; $('depth').value = params.get('depth'); }
    await report(showNodes());
  }
  // ?auto=1 (the browser test, docs/explore.md): a heatmap, then the centre pixel's trace.
  if (params.get('auto') === '1') {
    await report(heatmap());
    const size = imageSize();
    await report(tracePixel(size.width >> 1, size.height >> 1, size));
    showStep(Number(params.get('step') || 0));
  }
  document.body.dataset.loaded = '1';
}
main().catch((e) => { document.body.dataset.failed = e.message; });
