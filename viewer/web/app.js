// The viewer's page: settings, the progressive render with its HUD and
// overlays, cell renders, and the switch to the 3D modes (view3d.js).
// Everything it shows comes from the server's small JSON API and frames.
import {showHints} from '/web/hints.js';

const $ = (id) => document.getElementById(id);
const form = $('settings');

// What the page knows; exposed as window.viewer for the browser tests.
const viewer = {
  start: null,          // the command line's settings
  settings: null,       // the form's settings
  camera: null,         // the 3D view's camera when "render from here" set one
  cell: null,           // [x, y, w, h], (0, 0) bottom-left, or null
  job: null,            // the current render's id
  status: null,         // its last status
  mode: 'render',
  overlay: '',
  normalsJob: null,
  scene: null,          // /api/scene for the current settings
  view3d: null,         // the 3D module once loaded
  events: [],           // what happened, for the tests: {type, ...}
};
window.viewer = viewer;

// ------------------------------------------------------------------ API

async function api(path, body) {
  const init = body === undefined ? {} : {
    method: 'POST', headers: {'Content-Type': 'application/json'}, body: JSON.stringify(body)};
  const res = await fetch(path, init);
  if (!res.ok) {
    let msg = `HTTP ${res.status}`;
    try { msg = (await res.json()).error || msg; } catch (e) { /* not JSON */ }
    const err = new Error(msg);
    err.status = res.status;
    throw err;
  }
  const type = res.headers.get('Content-Type') || '';
  return type.startsWith('application/json') ? res.json() : res;
}
viewer.api = api;

// The job's status once it has more than `after` frames or has ended (the
// server waits up to 10 s before it answers anyway). When the server has
// too many such requests waiting it answers at once with "busy": then
// this one waits a second before the next.
async function waitStatus(job, after) {
  const st = await api(`/api/status?job=${job}&after=${after}`);
  if (st.busy && st.state === 'running' && !(st.frames > after)) await new Promise((r) => setTimeout(r, 1000));
  return st;
}
viewer.waitStatus = waitStatus;

function banner(text, kind) {
  const b = $('banner');
  const same = b.textContent === (text || '') && b.className === (kind || '') && b.hidden === !text;
  b.hidden = !text;
  b.textContent = text || '';
  b.className = kind || '';
  if (text && !same) viewer.events.push({type: 'banner', kind, text});
}
viewer.banner = banner;

// A job that has made no progress for a while (the worker's report): how
// long, and the function of the build's it is in. `ago`: seconds since
// the report arrived.
function stallText(stalled, what, ago) {
  const where = stalled.function ? `${stalled.function}${stalled.where ? ` (${stalled.where})` : ''}` : 'the build\'s code';
  return `${what} for ${Math.floor(stalled.seconds + ago)} s: an infinite loop in ${where}?`;
}
viewer.stallText = stallText;

// The TODO lines ("Part 1: raytrace_pixel (stages/part1_raytracing/pixel_sampling.cpp);
// one sample through the pixel centre, whatever -s"), one line per function
// still a stub: its part, name and file, and what the render does meanwhile.
function todoText(todo) {
  const lines = [];
  for (const line of todo) {
    const m = /^Part (\d+): (.*?) \(([^()]*)\)(?:; (.*))?$/.exec(line);
    if (!m) {
      lines.push({part: '?', text: `${line}: not written yet`});
      continue;
    }
    lines.push({part: m[1], text: `Part ${m[1]}, ${m[2]} (${m[3]}): not written yet${m[4] ? `; meanwhile ${m[4]}` : ''}`});
  }
  lines.sort((a, b) => a.part.localeCompare(b.part));
  return lines.map((l) => l.text).join('\n');
}

// ------------------------------------------------------------- settings

const numberFields = ['samples', 'light_samples', 'max_depth', 'threads', 'adaptive_batch', 'adaptive_tolerance',
                      'lens_radius', 'focal_distance', 'width', 'height', 'seed', 'part'];

// The parts, as the part selector names them (stages/README.md).
const PART_NAMES = ['rays, triangles, spheres', 'BVH', 'direct lighting', 'global illumination', 'adaptive sampling',
                    'mirror and glass', 'microfacet', 'environment light', 'depth of field'];

function fillParts(built) {
  const sel = form.elements.part;
  sel.innerHTML = '';
  for (let p = 1; p <= built; ++p) sel.add(new Option(`${p}: ${PART_NAMES[p - 1] || ''}`, String(p)));
}

// What the settings do at the chosen part that a student may not expect:
// the lens before part 9, the map's sampling before part 8, a scene's
// mirror, glass or metal before the part that writes it.
function settingsNotes(s, scene) {
  const notes = [];
  const part = s.part || 0;
  if (part < 9 && s.lens_radius > 0) notes.push(`lens radius (-b): the thin lens is part 9; at part ${part} the camera is a pinhole`);
  if (part >= 9 && !(s.lens_radius > 0)) notes.push('part 9: lens radius 0, a pinhole; set -b (and -d) for depth of field');
  if (s.env && part < 3) notes.push('environment map (-e): parts 1-2 shade normals; the map lights the scene from part 3 on');
  else if (s.env && part < 8) notes.push('environment map (-e): sampled uniformly over the sphere until part 8 (importance sampling)');
  const types = new Set(((scene && scene.materials) || []).map((m) => m.type));
  const later = [['mirror', 6], ['glass', 6], ['refraction', 6], ['microfacet', 7]].filter(([t, p]) => types.has(t) && part >= 3 && part < p);
  if (later.length) notes.push(`this scene's ${later.map(([t]) => t).join(', ')} material${later.length > 1 ? 's' : ''} ` +
                               `render black before part ${Math.min(...later.map(([, p]) => p))} (the course's starter code)`);
  return notes;
}
function showSettingsNotes() {
  const notes = viewer.settings ? settingsNotes(viewer.settings, viewer.scene) : [];
  $('settings-note').textContent = notes.join('\n');
}
viewer.settingsNotes = settingsNotes;

function fillSelect(select, files, current, none) {
  select.innerHTML = '';
  if (none) select.add(new Option(none, ''));
  for (const f of files) select.add(new Option(f.split('/').slice(-2).join('/'), f));
  if (current && !files.includes(current)) select.add(new Option(current, current));
  select.value = current || '';
}

function fillForm(s) {
  for (const k of numberFields) form.elements[k].value = s[k] === null || s[k] === undefined ? '' : s[k];
  form.elements.accumulate.checked = s.accumulate;
  form.elements.hemisphere.checked = s.hemisphere;
  form.elements.scene.value = s.scene;
  form.elements.camera_file.value = s.camera_file;
  form.elements.env.value = s.env;
}

function readForm() {
  const s = {};
  for (const k of numberFields) {
    const v = form.elements[k].value.trim();
    s[k] = v === '' ? null : Number(v);
  }
  // Seeds beyond 2^53 travel as text (JSON numbers would round them).
  const seed = form.elements.seed.value.trim();
  if (/^\d+$/.test(seed) && !Number.isSafeInteger(Number(seed))) s.seed = seed;
  s.accumulate = form.elements.accumulate.checked;
  s.hemisphere = form.elements.hemisphere.checked;
  s.scene = form.elements.scene.value;
  s.camera_file = form.elements.camera_file.value;
  s.env = form.elements.env.value;
  return s;
}

// The request for the current settings, view and cell.
function request(extra) {
  return Object.assign({}, viewer.settings, {camera: viewer.camera, cell: viewer.cell}, extra || {});
}
viewer.request = request;

let restartTimer = null;
function settingsChanged() {
  const before = viewer.settings;
  viewer.settings = readForm();
  if (before && (before.scene !== viewer.settings.scene || before.camera_file !== viewer.settings.camera_file)) {
    viewer.camera = null;  // a new scene or camera file starts from its own view
    viewer.cell = null;
  }
  if (before && (before.width !== viewer.settings.width || before.height !== viewer.settings.height)) viewer.cell = null;
  fillCases();
  showSettingsNotes();
  clearTimeout(restartTimer);
  restartTimer = setTimeout(() => {
    loadScene();
    if (viewer.mode === 'render') startRender();
    else if (viewer.view3d) viewer.view3d.settingsChanged();
  }, 120);
}
form.addEventListener('change', settingsChanged);

async function loadScene() {
  try {
    viewer.scene = await api('/api/scene', request());
    $('scene-name').textContent = `${viewer.scene.scene} — ${viewer.scene.triangles} triangles, ` +
                                  `${viewer.scene.spheres} spheres, ${viewer.scene.lights} lights`;
    showSettingsNotes();
  } catch (e) {
    banner(e.message, 'error');
  }
  return viewer.scene;
}
viewer.loadScene = loadScene;

// --------------------------------------------------------------- render

const canvas = $('render-canvas'), overlayCanvas = $('overlay-canvas');
const ctx = canvas.getContext('2d', {willReadFrequently: true});
const octx = overlayCanvas.getContext('2d');

function sizeCanvases(w, h) {
  if (canvas.width !== w || canvas.height !== h) {
    canvas.width = overlayCanvas.width = w;
    canvas.height = overlayCanvas.height = h;
    ctx.fillStyle = '#000';
    ctx.fillRect(0, 0, w, h);
  }
  // Small renders are shown enlarged by a whole factor (pixels stay square).
  const k = Math.max(1, Math.floor(Math.min(720 / w, 540 / h)));
  for (const c of [canvas, overlayCanvas]) {
    c.style.width = `${w * k}px`;
    c.style.height = `${h * k}px`;
  }
}

// Fetches one of a job's images (8-bit RGB from the top) as ImageData.
async function fetchImage(job, kind) {
  const res = await api(`/api/image?job=${job}&kind=${kind}`);
  const w = Number(res.headers.get('X-Width')), h = Number(res.headers.get('X-Height'));
  const rgb = new Uint8Array(await res.arrayBuffer());
  const img = new ImageData(w, h);
  for (let i = 0, j = 0; i < w * h; ++i, j += 3) {
    img.data[4 * i] = rgb[j];
    img.data[4 * i + 1] = rgb[j + 1];
    img.data[4 * i + 2] = rgb[j + 2];
    img.data[4 * i + 3] = 255;
  }
  return {img, w, h, pass: Number(res.headers.get('X-Pass')), scale: Number(res.headers.get('X-Scale'))};
}

// Draws a frame; a cell render only inside its cell.
function drawFrame(target, frame, cell) {
  if (cell) {
    const [x, y, w, h] = cell;
    target.putImageData(frame.img, 0, 0, x, frame.h - y - h, w, h);
  } else {
    target.putImageData(frame.img, 0, 0);
  }
}

async function startRender() {
  const req = request();
  banner('');
  // The running render's page work stops here (its last answers are not
  // drawn over the new render's, nor compared with a case).
  const previous = viewer.job;
  viewer.job = null;
  let st;
  try {
    st = await api('/api/render', req);
  } catch (e) {
    banner(e.message, 'error');
    viewer.events.push({type: 'refused', status: e.status, message: e.message});
    // Refused: the render before goes on being shown.
    if (previous && viewer.job === null) {
      viewer.job = previous;
      if (viewer.status && viewer.status.job === previous && viewer.status.state === 'running') poll(previous);
    }
    return null;
  }
  viewer.job = st.job;
  viewer.status = st;
  viewer.renderCell = req.cell;
  viewer.events.push({type: 'render', job: st.job, settings: st.settings, cell: req.cell});
  sizeCanvases(st.settings.width, st.settings.height);
  $('btn-stop').textContent = 'Stop';
  if (viewer.overlay === 'normals') startNormals();
  poll(st.job);
  return st.job;
}
viewer.startRender = startRender;

async function poll(job) {
  let after = 0;
  while (viewer.job === job) {
    let st;
    try {
      st = await waitStatus(job, after);
    } catch (e) {
      if (viewer.job === job) banner(`lost the server: ${e.message}`, 'error');
      return;
    }
    if (viewer.job !== job) return;
    viewer.status = st;
    viewer.statusAt = performance.now();
    if (st.stalled) viewer.events.push({type: 'stall', job, stalled: st.stalled});
    if (st.frames > after && st.frame) {
      after = st.frames;
      try {
        const f = await fetchImage(job, 'render');
        if (viewer.job !== job) return;
        drawFrame(ctx, f, viewer.renderCell);
        if (['rate', 'tests', 'diff'].includes(viewer.overlay)) await drawOverlay(job);
        viewer.events.push({type: 'frame', job, pass: f.pass, samples: st.frame.samples,
                            elapsed: st.frame.elapsed, seconds: st.frame.seconds});
      } catch (e) { /* a newer job replaced it */ }
    }
    hud(st);
    showJobMessages(st);
    if (st.state !== 'running') {
      $('btn-stop').textContent = 'Restart';
      // A render stopped between passes: say so (its last pass was compared).
      if (viewer.overlay === 'diff' && st.state !== 'done') await drawOverlay(job);
      viewer.events.push({type: 'end', job, state: st.state, message: st.message, samples: st.frame && st.frame.samples,
                          passes: st.passes});
      document.body.dataset.render = st.state;
      return;
    }
    document.body.dataset.render = 'running';
  }
}

function showJobMessages(st) {
  const lines = [];
  if (st.state === 'running' && st.stalled) {
    lines.push(stallText(st.stalled, 'no pixel finished', (performance.now() - viewer.statusAt) / 1000));
  }
  if (st.state === 'crashed' || st.state === 'failed') lines.push(st.message);
  if (st.todo.length) lines.push(todoText(st.todo));
  if (lines.length) banner(lines.join('\n'), st.state === 'crashed' || st.state === 'failed' ? 'error' : 'todo');
  else if (viewer.stallShown) banner('');  // moving again
  viewer.stallShown = st.state === 'running' && !!st.stalled;
}

function fmt(x, d = 2) { return Number(x).toFixed(d); }

// The render's figures and the time since it started (counting on between
// two answers of the server while it runs).
function hud(st) {
  const f = st.frame;
  const wall = st.wall + (st.state === 'running' && viewer.statusAt ? (performance.now() - viewer.statusAt) / 1000 : 0);
  let text = `${st.state} · ${fmt(wall, 1)} s`;
  if (f) {
    const rays = f.rays;
    text = `samples ${f.samples}/${st.target} (pass ${f.pass + 1}) · ${rays.toLocaleString()} rays · ` +
           `${fmt(f.seconds > 0 ? rays / f.seconds / 1e6 : 0)} Mrays/s · ` +
           `${fmt(rays ? f.tests / rays : 0)} tests/ray · ${fmt(wall, 1)} s · ${st.state}`;
  }
  $('hud').textContent = text;
}
setInterval(() => {
  const st = viewer.status;
  if (!st || st.state !== 'running' || st.job !== viewer.job) return;
  hud(st);
  if (st.stalled) showJobMessages(st);
}, 1000);

// Draws the overlay over render `renderJob` (default: the current one).
async function drawOverlay(renderJob) {
  octx.clearRect(0, 0, overlayCanvas.width, overlayCanvas.height);
  overlayCanvas.style.opacity = $('overlay-opacity').value / 100;
  $('overlay-note').textContent = '';
  showHints($('diff-hints'), null);
  if (!viewer.overlay) return;
  if (viewer.overlay === 'diff') return drawDiff(renderJob || viewer.job);
  const job = viewer.overlay === 'normals' ? viewer.normalsJob : viewer.job;
  if (!job) return;
  // Only images that exist: a finished normals job, a render with a frame.
  if (viewer.overlay === 'normals' ? viewer.normalsReady !== job
                                   : !(viewer.status && viewer.status.job === job && viewer.status.frame)) return;
  try {
    const f = await fetchImage(job, viewer.overlay === 'normals' ? 'render' : viewer.overlay);
    // The render's maps cover its cell only; the normals, the whole image.
    const cell = viewer.overlay === 'normals' ? null : viewer.renderCell;
    if (f.w === overlayCanvas.width && f.h === overlayCanvas.height) drawFrame(octx, f, cell);
    if (viewer.overlay === 'tests') {
      $('hud').dataset.scale = f.scale;
      $('overlay-note').textContent = `intersection tests per ray: blue 0, green ${fmt(f.scale / 2)}, red ${fmt(f.scale)}`;
    } else if (viewer.overlay === 'rate') {
      $('overlay-note').textContent = 'samples taken / samples per pixel: blue 0, green 0.5, red 1';
    } else {
      $('overlay-note').textContent = 'normals (part 2 shading, 1 sample per pixel)';
    }
  } catch (e) { /* no frame yet */ }
}

// The grader's own comparison of render `job`'s last pass with a case's
// reference (its committed mean and variance): |z| per pixel. An earlier
// pass of the case's render is answered with when the difference comes
// (202); each pass asks again.
async function drawDiff(job) {
  const name = $('case').value;
  if (!name || !job) {
    $('overlay-note').textContent = 'Pick a grading case (its settings must be the render\'s).';
    return;
  }
  const st = viewer.status;
  if (!st || st.job !== job || !st.frame) {
    $('overlay-note').textContent = 'The difference is drawn once the render has a pass.';
    return;
  }
  try {
    const res = await api(`/api/diff?job=${job}&case=${encodeURIComponent(name)}`);
    if (job !== viewer.job) return;  // a newer render replaced it meanwhile
    if (!(res instanceof Response)) {
      $('overlay-note').textContent = `${name}: ${res.pending}`;
      viewer.events.push({type: 'diff_pending', job, case: name, message: res.pending});
      return;
    }
    const w = Number(res.headers.get('X-Width')), h = Number(res.headers.get('X-Height'));
    const rgb = new Uint8Array(await res.arrayBuffer());
    if (job !== viewer.job) return;
    const img = new ImageData(w, h);
    for (let i = 0; i < w * h; ++i) {
      img.data.set([rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2], 255], 4 * i);
    }
    octx.putImageData(img, 0, 0);
    const summary = res.headers.get('X-Summary');
    const likely = JSON.parse(res.headers.get('X-Hints') || '{"hints": []}');
    $('overlay-note').textContent = `${name}: ${summary} (|z| per pixel, black 0 to white at the threshold, red beyond)`;
    showHints($('diff-hints'), likely);
    viewer.events.push({type: 'diff', job, case: name, summary, hints: likely.hints, note: likely.note});
  } catch (e) {
    if (job !== viewer.job) return;
    $('overlay-note').textContent = e.message;
    viewer.events.push({type: 'diff', job, case: name, error: e.message});
  }
}

function fillCases() {
  const sel = $('case'), scene = viewer.settings && viewer.settings.scene;
  const mine = (viewer.cases || []).filter((c) => c.settings.scene === scene);
  const prev = sel.value;
  sel.innerHTML = '';
  sel.add(new Option(mine.length ? '(pick a case)' : '(no case on this scene)', ''));
  for (const c of mine) sel.add(new Option(c.name, c.name));
  if (mine.some((c) => c.name === prev)) sel.value = prev;
}

$('btn-apply-case').addEventListener('click', () => {
  const c = (viewer.cases || []).find((x) => x.name === $('case').value);
  if (!c) return;
  const keep = {threads: viewer.settings.threads, seed: viewer.settings.seed};
  fillForm(Object.assign({}, c.settings, keep));
  viewer.cell = null;
  viewer.camera = null;
  $('cell-box').hidden = true;
  $('overlay').value = viewer.overlay = 'diff';
  // At once (not after the form's short delay), so that no earlier render
  // ends in between and is compared with the case.
  clearTimeout(restartTimer);
  viewer.settings = readForm();
  fillCases();
  $('case').value = c.name;
  loadScene();
  startRender();
});
$('case').addEventListener('change', () => { if (viewer.overlay === 'diff') drawOverlay(); });

async function startNormals() {
  try {
    const st = await api('/api/normals', request());
    viewer.normalsJob = st.job;
    let s = st;
    while (s.state === 'running' && viewer.normalsJob === st.job) s = await waitStatus(st.job, 0);
    if (s.state === 'done') viewer.normalsReady = st.job;
    if (viewer.normalsJob === st.job) await drawOverlay();
  } catch (e) {
    banner(e.message, 'error');
  }
}

$('overlay').addEventListener('change', () => {
  viewer.overlay = $('overlay').value;
  if (viewer.overlay === 'normals') startNormals();
  else drawOverlay();
});
$('overlay-opacity').addEventListener('input', () => { overlayCanvas.style.opacity = $('overlay-opacity').value / 100; });

async function stopOrRestart() {
  if (viewer.status && viewer.status.state === 'running') {
    await api('/api/stop', {});
  } else {
    startRender();
  }
}
$('btn-stop').addEventListener('click', stopOrRestart);

function download(url) {
  const a = document.createElement('a');
  a.href = url;
  a.download = '';
  document.body.appendChild(a);
  a.click();
  a.remove();
}
$('btn-png').addEventListener('click', () => viewer.job && download(`/api/png?job=${viewer.job}`));
$('btn-pfm').addEventListener('click', () => viewer.job && download(`/api/pfm?job=${viewer.job}`));

// ----------------------------------------------------------- cell render

let drag = null;
function canvasPixel(e) {
  const r = canvas.getBoundingClientRect();
  return [Math.floor((e.clientX - r.left) * canvas.width / r.width),
          Math.floor((e.clientY - r.top) * canvas.height / r.height)];
}
canvas.addEventListener('mousedown', (e) => {
  if (!$('cell-mode').checked) return;
  drag = {from: canvasPixel(e)};
  e.preventDefault();
});
function dragRect(e) {
  const [x0, y0] = drag.from, [x1, y1] = canvasPixel(e);
  const clamp = (v, hi) => Math.max(0, Math.min(hi, v));
  const left = clamp(Math.min(x0, x1), canvas.width - 1), top = clamp(Math.min(y0, y1), canvas.height - 1);
  const right = clamp(Math.max(x0, x1), canvas.width - 1), bottom = clamp(Math.max(y0, y1), canvas.height - 1);
  return {left, top, w: right - left + 1, h: bottom - top + 1};
}
window.addEventListener('mousemove', (e) => {
  if (!drag) return;
  const r = dragRect(e), box = $('cell-box'), scale = canvas.getBoundingClientRect().width / canvas.width;
  Object.assign(box.style, {left: `${r.left * scale}px`, top: `${r.top * scale}px`,
                            width: `${r.w * scale}px`, height: `${r.h * scale}px`});
  box.hidden = false;
});
window.addEventListener('mouseup', (e) => {
  if (!drag) return;
  const r = dragRect(e);
  drag = null;
  // -p counts rows from the bottom.
  viewer.cell = [r.left, canvas.height - r.top - r.h, r.w, r.h];
  startRender();
});
$('btn-whole').addEventListener('click', () => {
  viewer.cell = null;
  $('cell-box').hidden = true;
  startRender();
});

// ----------------------------------------------------------------- modes

async function setMode(mode) {
  viewer.mode = mode;
  for (const b of document.querySelectorAll('nav button')) b.classList.toggle('active', b.dataset.mode === mode);
  $('render-view').hidden = mode !== 'render';
  $('three-view').hidden = mode === 'render';
  $('debug-panel').hidden = mode !== 'debug';
  if (viewer.debug) viewer.debug.overlay.group.visible = mode === 'debug';
  document.body.dataset.mode = mode;
  if (mode === 'render') return;
  if (!viewer.view3d) {
    try {
      const m = await import('/web/view3d.js');
      viewer.view3d = m.create(viewer, {api, banner, startRender, setMode, todoText});
    } catch (e) {
      banner(`The 3D views need three.js: ${e.message} (run scripts/setup.sh, which installs it with npm ci)`, 'error');
      return;
    }
  }
  await viewer.view3d.show(mode === 'debug' ? 'camera' : mode);
  if (mode === 'debug') {
    if (!viewer.debug) viewer.debug = (await import('/web/debug.js')).create(viewer, {api, banner, todoText});
    viewer.debug.show();
  }
}
viewer.setMode = setMode;
for (const b of document.querySelectorAll('nav button')) b.addEventListener('click', () => setMode(b.dataset.mode));

// ------------------------------------------------------------------ keys

function bump(name, f) {
  const el = form.elements[name];
  el.value = Math.max(Number(el.min || 0), Math.round(f(Number(el.value))));
  settingsChanged();
}

window.addEventListener('keydown', (e) => {
  if (e.target.closest && e.target.closest('input, select, textarea')) return;
  if (e.ctrlKey || e.metaKey || e.altKey) return;
  const k = e.key;
  if (k === 'r' || k === 'R') {
    if (viewer.mode === 'render') startRender(); else setMode('render');
  } else if (k === 'e' || k === 'E') setMode('camera');
  else if (k === 'v' || k === 'V') setMode('bvh');
  else if (k === 'd' || k === 'D') setMode('debug');
  else if (k === '[') bump('samples', (v) => v / 2);
  else if (k === ']') bump('samples', (v) => v * 2);
  else if (k === '-') bump('light_samples', (v) => v / 2);
  else if (k === '+' || k === '=') bump('light_samples', (v) => v * 2);
  else if (k === 'c' || k === 'C') $('cell-mode').checked = !$('cell-mode').checked;
  else if (k === 's' || k === 'S') $('btn-png').click();
  else if (k === ' ') stopOrRestart();
  else if (viewer.mode === 'bvh' && viewer.view3d) {
    if (k === '<' || k === ',' || k === 'ArrowLeft') viewer.view3d.go('left');
    else if (k === '>' || k === '.' || k === 'ArrowRight') viewer.view3d.go('right');
    else if (k === '?' || k === '/' || k === 'ArrowUp') viewer.view3d.go('parent');
    else return;
  } else return;
  e.preventDefault();
});

// ----------------------------------------------------------------- start

async function main() {
  let st;
  try {
    st = await api('/api/state');
  } catch (e) {
    banner(`Cannot reach the viewer: ${e.message}`, 'error');
    return;
  }
  viewer.start = st.start;
  // Why the settings start at this part (the build's parts still stubbed).
  $('start-note').textContent = st.start_note || '';
  $('start-note').hidden = !st.start_note;
  fillParts(st.parts_built);
  fillSelect(form.elements.scene, st.scenes, st.start.scene);
  fillSelect(form.elements.camera_file, st.cameras, st.start.camera_file, '(the scene\'s camera)');
  fillSelect(form.elements.env, st.envs, st.start.env, '(none)');
  fillForm(st.start);
  viewer.settings = readForm();
  viewer.cases = st.cases;
  viewer.cell = st.start.cell;  // -p on the command line
  fillCases();
  await loadScene();
  // Ready once the first render has its job (the tests wait on it).
  await startRender();
  document.body.dataset.ready = '1';
}
main();
