// Debug mode (D): the intersection tester, the light-sample tester, the
// path inspector, the BSDF sampler and the environment map's sampling
// density, each a call of the build's own code in a worker
// (POST /api/debug/intersect|lights|path|bsdf|envmap), drawn in the 3D view
// (debug3d.js) and listed in the panel (the last two by debug_sampling.js).
import {COLORS, createOverlay} from '/web/debug3d.js';
import {createSampling} from '/web/debug_sampling.js';

const $ = (id) => document.getElementById(id);

// "1, 2, 3" or "1 2 3" -> [1, 2, 3]; "nan", "inf", "-inf" and anything else
// that is not a number travel as text, for the server to refuse or accept.
export function parseVec(text) {
  const parts = String(text).trim().split(/[\s,]+/).filter((p) => p !== '');
  return parts.map(parseNum);
}
function parseNum(t) {
  const s = String(t).trim();
  if (/^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/.test(s)) return Number(s);
  return s.toLowerCase();
}

// Numbers as the page shows them: floats to 6 significant digits.
function f(x) {
  if (typeof x === 'string') return x;
  if (x === undefined || x === null) return '—';
  if (Array.isArray(x)) return `(${x.map(f).join(', ')})`;
  if (Number.isInteger(x) && Math.abs(x) < 1e9) return String(x);
  return Number(x).toPrecision(6).replace(/(\.\d*?)0+(e|$)/, '$1$2').replace(/\.(e|$)/, '$1');
}
// A colour: one number when its channels are equal (grey), else three.
function fc(c) {
  if (Array.isArray(c) && c.length === 3 && c[0] === c[1] && c[1] === c[2]) return f(c[0]);
  return f(c);
}
const num = (x) => (typeof x === 'string' ? (x === 'inf' ? Infinity : x === '-inf' ? -Infinity : NaN) : x);
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, k) => [a[0] * k, a[1] * k, a[2] * k];
const len = (a) => Math.hypot(a[0], a[1], a[2]);
function el(tag, attrs, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === 'class') e.className = v; else e.setAttribute(k, v);
  }
  for (const c of children) e.append(c instanceof Node ? c : document.createTextNode(String(c)));
  return e;
}

export function create(viewer, hooks) {
  const three = viewer.view3d.three;
  const overlay = createOverlay(three);
  const state = {tool: 'path', last: {}};
  viewer.debugState = state;
  const TOOLS = ['intersect', 'lights', 'path', 'bsdf', 'envmap'];

  // The scene's size, for drawing escaped rays and arrows in proportion.
  function sceneSize() {
    const b = viewer.scene && viewer.scene.bounds;
    return b ? Math.max(1e-3, len([b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]])) : 1;
  }

  function showTool(tool) {
    state.tool = tool;
    for (const b of document.querySelectorAll('#debug-tabs button')) b.classList.toggle('active', b.dataset.tool === tool);
    for (const s of document.querySelectorAll('#debug-panel fieldset')) s.hidden = s.dataset.tool !== tool;
    overlay.clear();
    const last = state.last[tool];
    if (last && last.ok) draw(tool, last.result);
    overlay.redraw();
    // The density is shown as soon as its tab opens with a map chosen.
    if (tool === 'envmap' && !last && viewer.settings.env && document.body.dataset.debug !== 'running') runEnvmap();
  }

  // One call: started in a worker and followed (how long it runs, where it
  // is stuck; a Stop button) until it ends; then its result (or the error)
  // goes to the panel, the 3D view and the page's event log.
  async function call(tool, input) {
    const out = $(`dbg-${tool}-out`);
    out.textContent = 'starting…';
    out.className = 'dbg-out';
    document.body.dataset.debug = 'running';
    let result = null, error = null, status = 200;
    try {
      let st = await hooks.api(`/api/debug/${tool}`, viewer.request({debug: input, cell: null}));
      while (st.state === 'running') {
        showRunning(tool, out, st);
        st = await viewer.waitStatus(st.job, 0);
      }
      result = await hooks.api(`/api/debug-result?job=${st.job}`);
    } catch (e) {
      error = e.message;
      status = e.status || 0;
    }
    clearInterval(state.ticker);
    const entry = {type: 'debug', tool, status, ok: !error, result, error, input};
    state.last[tool] = entry;
    viewer.events.push(entry);
    out.innerHTML = '';
    overlay.clear();
    if (error) {
      out.className = 'dbg-out error';
      // 409: stopped (by Stop, by a newer call); 5xx: the worker failed.
      out.textContent = status >= 500 || status === 409 ? error : `refused (HTTP ${status}): ${error}`;
      if (status !== 409) hooks.banner(`${toolName(tool)}: ${error}`, 'error');
    } else {
      hooks.banner('');
      const problems = [];
      if (result.error) problems.push(result.error);
      // The stubs the tool reached, and any TODO line the worker printed.
      const todos = new Set([...(result.todos || []).map((t) => t.replace(/^TODO: implement /, '')), ...(result.worker_todo || [])]);
      if (todos.size) problems.push(hooks.todoText([...todos]));
      if (problems.length) hooks.banner(problems.join('\n'), result.error ? 'error' : 'todo');
      if (tool === 'intersect') showIntersection(out, result);
      else if (tool === 'lights') showLights(out, result);
      else if (tool === 'bsdf') sampling.showBsdf(out, result);
      else if (tool === 'envmap') sampling.showEnvmap(out, result);
      else showPath(out, result);
      draw(tool, result);
    }
    overlay.redraw();
    document.body.dataset.debug = error ? 'error' : 'done';
    return entry;
  }

  // While a call runs: how long, and once the worker says it is stuck,
  // where (an endless loop in the build's code, most likely); Stop ends it.
  function showRunning(tool, out, st) {
    clearInterval(state.ticker);
    const received = performance.now();
    let label = $(`dbg-${tool}-running`);
    if (!label) {
      out.innerHTML = '';
      label = el('span', {id: `dbg-${tool}-running`});
      const stop = el('button', {class: 'small', id: `dbg-${tool}-stop`}, 'Stop');
      stop.addEventListener('click', () => hooks.api('/api/stop', {job: st.job}).catch((e) => hooks.banner(e.message, 'error')));
      out.append(label, ' ', stop);
    }
    const draw = () => {
      const ago = (performance.now() - received) / 1000;
      label.textContent = `running… ${Math.floor(st.wall + ago)} s` +
        (st.stalled ? ` — ${viewer.stallText(st.stalled, 'no answer', ago)}` : '');
    };
    draw();
    state.ticker = setInterval(draw, 1000);
  }

  function toolName(tool) {
    return {intersect: 'Intersection tester', lights: 'Light-sample tester', path: 'Path inspector', bsdf: 'BSDF sampler',
            envmap: 'Environment density'}[tool];
  }

  function draw(tool, r) {
    if (tool === 'intersect') drawIntersection(r);
    else if (tool === 'lights') drawLights(r);
    else if (tool === 'bsdf') sampling.drawBsdf(r);
    else if (tool === 'path') drawPath(r);
  }

  function kv(out, rows) {
    const t = el('table', {class: 'kv'});
    for (const [k, v, cls] of rows) t.append(el('tr', cls ? {class: cls} : {}, el('th', {}, k), el('td', {}, v)));
    out.append(t);
    return t;
  }
  const sampling = createSampling({el, f, fc, num, kv, overlay, sceneSize, COLORS});

  // ---------------------------------------------------- intersection tester

  function intersectInput() {
    const shape = $('dbg-shape').value;
    const input = {ray: {origin: parseVec($('dbg-origin').value), direction: parseVec($('dbg-direction').value),
                         min_t: parseNum($('dbg-min-t').value), max_t: parseNum($('dbg-max-t').value)}};
    if (shape === 'triangle') {
      input.triangle = {p1: parseVec($('dbg-p1').value), p2: parseVec($('dbg-p2').value), p3: parseVec($('dbg-p3').value)};
    } else if (shape === 'sphere') {
      input.sphere = {center: parseVec($('dbg-center').value), radius: parseNum($('dbg-radius').value)};
    } else {
      input.primitive = parseNum($('dbg-primitive').value);
    }
    return input;
  }

  function showIntersection(out, r) {
    const rows = [['function', r.function], ['result', r.hit ? 'hit' : 'miss', r.hit ? 'hit' : 'miss']];
    if (r.hit) rows.push(['t', f(r.t)], ['point', f(r.point)], ['normal', f(r.normal)], ['material', f(r.material)]);
    rows.push(['r.max_t after', f(r.max_t_after)]);
    if (r.primitive !== undefined) rows.push(['primitive', f(r.primitive)]);
    if (r.error) rows.push(['error', r.error, 'error']);
    const t = kv(out, rows);
    t.id = 'dbg-intersect-table';
  }

  function drawIntersection(r) {
    const o = r.ray.origin, d = r.ray.direction;
    const size = sceneSize();
    const tEnd = r.hit ? num(r.t) : Math.min(num(r.ray.max_t), 2 * size / Math.max(1e-12, len(d)));
    overlay.segments([[o, add(o, scale(d, tEnd))]], r.hit ? COLORS.ray : COLORS.untested);
    overlay.points([o], COLORS.ray, 7);
    const tri = r.triangle || (state.lastInput && state.lastInput.triangle &&
                               [state.lastInput.triangle.p1, state.lastInput.triangle.p2, state.lastInput.triangle.p3]);
    const sph = r.sphere || (state.lastInput && state.lastInput.sphere &&
                             [state.lastInput.sphere.center, state.lastInput.sphere.radius]);
    if (tri && tri.every((p) => p.every((x) => typeof x === 'number'))) overlay.loop(tri, COLORS.shape);
    else if (sph && typeof sph[1] === 'number') overlay.sphere(sph[0], sph[1], COLORS.shape);
    if (r.hit) {
      overlay.points([r.point], COLORS.hit, 9);
      overlay.arrow(r.point, r.normal, 0.08 * size, COLORS.normal);
    }
  }

  // ---------------------------------------------------- light-sample tester

  function lightsInput() {
    return {light: parseNum($('dbg-light').value), point: parseVec($('dbg-lpoint').value),
            normal: parseVec($('dbg-lnormal').value), samples: parseNum($('dbg-lsamples').value),
            seed: parseNum($('dbg-lseed').value)};
  }

  // Where each sample landed: point + wi * distance (lights at infinity: none).
  function samplePoints(r) {
    return r.samples.filter((s) => Number.isFinite(num(s.distance)) && num(s.pdf) > 0)
      .map((s) => add(r.point, scale(s.wi, num(s.distance))));
  }

  function showLights(out, r) {
    const n = r.samples.length;
    const pos = r.samples.filter((s) => num(s.pdf) > 0);
    const tested = r.samples.filter((s) => s.shadow_tested);
    const blocked = tested.filter((s) => s.blocked).length;
    const mean = (xs) => (xs.length ? xs.reduce((a, b) => a + b, 0) / xs.length : NaN);
    kv(out, [['light', `${r.light} (${r.light_type})`], ['samples', n], ['pdf > 0', pos.length],
             ['mean pdf', f(mean(pos.map((s) => num(s.pdf))))],
             ['mean distance', f(mean(pos.map((s) => num(s.distance))))],
             ['shadow rays', `${tested.length} traced, ${blocked} blocked`]].concat(r.error ? [['error', r.error, 'error']] : []));
    const t = el('table', {class: 'steps', id: 'dbg-lights-table'});
    t.append(el('tr', {}, ...['#', 'u', 'wi', 'distance', 'pdf', 'radiance', 'cos θ', 'shadow'].map((h) => el('th', {}, h))));
    r.samples.slice(0, 32).forEach((s, i) => t.append(el('tr', {},
      ...[i, f(s.u), f(s.wi), f(s.distance), f(s.pdf), fc(s.radiance), f(s.cos_theta),
          s.shadow_tested ? (s.blocked ? 'blocked' : 'lit') : 'not traced'].map((v) => el('td', {}, v)))));
    out.append(t);
    if (n > 32) out.append(el('div', {class: 'note'}, `the first 32 of ${n} samples; all are drawn`));
  }

  function lightCorners(shape) {
    const p = shape.position, x = scale(shape.dim_x, 0.5), y = scale(shape.dim_y, 0.5);
    return [add(add(p, x), y), add(add(p, scale(x, -1)), y), add(add(p, scale(x, -1)), scale(y, -1)),
            add(add(p, x), scale(y, -1))];
  }

  function drawLights(r) {
    const size = sceneSize();
    if (r.light_shape && r.light_shape.type === 'area') overlay.loop(lightCorners(r.light_shape), COLORS.light);
    const lit = [], blocked = [], other = [];
    for (const s of r.samples) {
      const d = num(s.distance);
      const to = add(r.point, scale(s.wi, Number.isFinite(d) ? d : size));
      (s.shadow_tested ? (s.blocked ? blocked : lit) : other).push([r.point, to]);
    }
    overlay.segments(lit, COLORS.shadow);
    overlay.segments(blocked, COLORS.shadow_blocked);
    overlay.segments(other, COLORS.untested);
    overlay.points(samplePoints(r), COLORS.sample, 5);
    overlay.points([r.point], COLORS.point, 9);
    overlay.arrow(r.point, r.normal, 0.08 * size, COLORS.normal);
    state.samplePoints = samplePoints(r);
  }

  // --------------------------------------------------------- path inspector

  function pathInput() {
    return {x: parseNum($('dbg-x').value), y: parseNum($('dbg-y').value), sample: parseNum($('dbg-sample').value)};
  }

  function showPath(out, r) {
    const top = [['pixel', `(${r.pixel[0]}, ${r.pixel[1]}), sample ${r.sample} of ${r.samples_per_pixel}, seed ${r.seed}, part ${r.part}`],
                 ['camera ray', `${f(r.camera_ray.origin)} → ${f(r.camera_ray.direction)}`],
                 ['zero bounce (emission seen)', fc(r.zero_bounce)],
                 ['total (returned)', fc(r.returned)],
                 ['sum of the steps', fc(r.sum_of_contributions)],
                 // With stubs in the way the sum agrees with nothing worth checking.
                 (r.todos || []).length
                   ? ['agrees', 'not checked: the functions this sample ran are still stubs (the TODO lines above)', 'error']
                   : ['agrees', r.exact ? 'yes, exactly' : r.agrees ? 'yes, within rounding' : 'NO: the estimator computed something else',
                      r.agrees ? '' : 'error'],
                 ['end', r.end]];
    for (const n of r.notes || []) top.push(['note', n, 'error']);
    if (r.error) top.push(['error', r.error, 'error']);
    const t = kv(out, top);
    t.id = 'dbg-path-summary';
    const tbl = el('table', {class: 'steps', id: 'dbg-path-table'});
    const heads = ['bounce', 'material', 'direct', 'f', 'cos θ', 'pdf', 'roulette', 'path weight', 'radiance added'];
    tbl.append(el('tr', {}, ...heads.map((h) => el('th', {}, h))));
    for (const s of r.steps) {
      const b = s.bsdf_sample;
      const rr = s.roulette;
      const roulette = rr && rr.applies ? `${f(rr.draws)} vs ${f(rr.continue_probability)}` : '—';
      // A delta step (mirror, glass) has no direct estimate: its light is
      // what its bounce ray reaches.
      const direct = s.delta ? (s.reached ? `reached ${fc(s.reached)}${s.reached_counted ? '' : ' (not counted)'}` : '— (delta)')
                             : `${fc(s.direct)}${s.direct_counted === false ? ' (not counted)' : ''}`;
      const material = s.material.replace(/-material /, ' ') +
                       (s.bsdf_model === 'not rendered' ? ' — not rendered at this part: black' : '');
      const expected = lightEstimate(s);
      const mismatch = expected && !sameColour(expected, s.direct);
      tbl.append(el('tr', {'data-bounce': s.bounce, class: mismatch ? 'mismatch' : ''},
        el('td', {}, s.bounce), el('td', {}, material), el('td', {}, direct), el('td', {}, b ? fc(b.f) : '—'),
        el('td', {}, b ? f(b.cos_theta) : '—'), el('td', {}, b ? f(b.pdf) : '—'), el('td', {}, roulette),
        el('td', {}, fc(s.path_weight)), el('td', {class: 'added'}, fc(s.radiance_added))));
      // The light samples (or hemisphere probes) of the direct estimate, under the step.
      const ls = el('div', {class: 'samples'});
      const hitline = el('div', {class: 'hitline'}, `hit point ${f(s.point)}, normal ${f(s.normal)}, primitive ${s.primitive}, ` +
                         `t ${f(s.t)} `);
      const again = el('button', {class: 'small', title: 'this ray against this primitive, in the intersection tester'}, 'test the hit');
      again.addEventListener('click', () => pickHit(s));
      const here = el('button', {class: 'small', title: 'the light-sample tester from this point'}, 'sample lights here');
      here.addEventListener('click', () => pickPoint(s));
      hitline.append(again, ' ', here);
      ls.append(hitline);
      if (b) ls.append(bsdfLine(s, b));
      if (s.delta) {
        ls.append(el('div', {class: 'delta'}, `a delta BSDF (${s.bsdf_model}): no light samples; its light is what the bounce ray ` +
          `reaches${s.reached ? `, ${fc(s.reached)}, ${s.reached_counted ? 'added as path weight × f·|cos θ|/pdf × reached' : 'not counted here (-o, --indirect-only)'}` : ''}`));
      } else {
        ls.append(el('div', {}, `${s.estimator || 'no direct estimate'}:`));
      }
      if (expected) {
        ls.append(el('div', {class: mismatch ? 'mismatch' : 'match'},
          `the light samples' f·L·cos θ/pdf, averaged per light and summed: ${fc(expected)}` +
          (mismatch ? ` ≠ direct ${fc(s.direct)} (ratio ${f(ratio(s.direct, expected))}): the estimate returned ` +
                      'something else than the light samples give' : ' = direct')));
      }
      for (const l of s.light_samples || []) {
        ls.append(el('div', {class: l.verdict === 'lit' ? 'lit' : 'dark'},
          `light ${l.light}: pdf ${f(l.pdf)}, L ${fc(l.radiance)}, cos θ ${f(l.cos_theta)}, f ${fc(l.bsdf)} → ${l.verdict}` +
          (l.verdict === 'lit' ? `, f·L·cos θ/pdf ${fc(l.contribution)}` : '')));
      }
      const hs = s.hemisphere_samples || [];
      if (hs.length) ls.append(el('div', {}, `${hs.length} hemisphere probes, ${hs.filter((p) => p.hit).length} hit`));
      tbl.append(el('tr', {class: 'sub'}, el('td', {}), el('td', {colspan: heads.length - 1}, ls)));
    }
    tbl.append(el('tr', {class: 'total'}, el('td', {colspan: heads.length - 1}, 'total: zero bounce + radiance added, in order'),
                  el('td', {id: 'dbg-path-total'}, fc(r.returned))));
    out.append(tbl);
    out.append(el('div', {class: 'note'}, 'Colours with equal channels show one number. radiance added = path weight × direct; ' +
                  'the next path weight = path weight × f × |cos θ| / pdf (÷ the continue probability when roulette applies); a refracted wi lies below the surface (cos θ < 0).'));
  }

  // What the step's BSDF sample did: reflected or refracted, the directions
  // in the local frame (z = the normal), f, pdf (for a delta BSDF the
  // probability of the choice it made) and the weight it gives the path.
  function bsdfLine(s, b) {
    const cos = Math.abs(num(b.cos_theta)), pdf = num(b.pdf);
    const weight = pdf > 0 ? fc(b.f.map((x) => num(x) * cos / pdf)) : '—';
    const line = el('div', {class: 'bsdf'},
      `BSDF sample (${s.bsdf_model}${s.delta ? ', delta' : ''}): ${b.scatter}, wo ${f(b.wo_local)} → wi ${f(b.wi_local)} ` +
      `(local, z = normal), f ${fc(b.f)}, pdf ${f(b.pdf)}${s.delta ? ' (the probability of this choice)' : ''}, ` +
      `|cos θ| ${f(cos)}, f·|cos θ|/pdf ${weight}`);
    line.dataset.scatter = b.scatter;
    return line;
  }

  // A step's ray and primitive into the intersection tester; its point and
  // normal into the light-sample tester.
  const text3 = (a) => a.map((x) => String(x)).join(', ');
  function pickHit(s) {
    $('dbg-shape').value = 'primitive';
    $('dbg-shape').dispatchEvent(new Event('change'));
    $('dbg-primitive').value = s.primitive;
    $('dbg-origin').value = text3(s.ray.origin);
    $('dbg-direction').value = text3(s.ray.direction);
    $('dbg-min-t').value = String(s.ray.min_t);
    $('dbg-max-t').value = String(s.ray.max_t);
    showTool('intersect');
    return runIntersect();
  }
  function pickPoint(s) {
    $('dbg-lpoint').value = text3(s.point);
    $('dbg-lnormal').value = text3(s.normal);
    showTool('lights');
    return runLights();
  }

  // What a light-sampling estimate should return from its samples: for each
  // light, the mean of f·L·cos θ/pdf over the samples drawn (blocked and
  // skipped ones count as zero), summed over the lights. Null when there is
  // nothing to check (hemisphere sampling, no samples).
  function lightEstimate(s) {
    if (s.estimator !== 'light sampling' || !(s.light_samples || []).length) return null;
    const per = new Map();
    for (const l of s.light_samples) {
      const e = per.get(l.light) || {n: 0, sum: [0, 0, 0]};
      e.n += 1;
      if (l.verdict === 'lit') e.sum = add(e.sum, l.contribution.map(num));
      per.set(l.light, e);
    }
    let total = [0, 0, 0];
    for (const e of per.values()) total = add(total, scale(e.sum, 1 / e.n));
    return total.map(Math.fround);
  }
  function sameColour(a, b) {
    return a.every((x, i) => Math.abs(x - num(b[i])) <= 1e-5 * Math.max(Math.abs(x), Math.abs(num(b[i])), 1e-30) || x === num(b[i]));
  }
  function ratio(a, b) {
    const i = [0, 1, 2].reduce((k, j) => (Math.abs(b[j]) > Math.abs(b[k]) ? j : k), 0);
    return num(a[i]) / b[i];
  }

  function drawPath(r) {
    const size = sceneSize();
    const by = {};
    for (const s of r.segments) {
      const to = s.to || add(s.from, scale(s.direction, 0.6 * size / Math.max(1e-12, len(s.direction))));
      (by[s.kind] = by[s.kind] || []).push([s.from, to]);
    }
    for (const [kind, pairs] of Object.entries(by)) overlay.segments(pairs, COLORS[kind] || COLORS.untested);
    overlay.points([r.camera_ray.origin], COLORS.camera, 9);
    overlay.points(r.steps.map((s) => s.point), COLORS.hit, 8);
    for (const s of r.steps) overlay.arrow(s.point, s.normal, 0.05 * size, COLORS.normal);
    state.pathSegments = r.segments;
  }

  // ------------------------------------------------------------ the panel

  // The render's image, to click a pixel on (the path inspector's and the
  // BSDF sampler's copies).
  function copyRender() {
    const src = $('render-canvas');
    for (const dst of [$('dbg-pick'), $('dbg-bpick')]) {
      dst.width = src.width;
      dst.height = src.height;
      dst.getContext('2d').drawImage(src, 0, 0);
    }
  }
  function pickPixel(canvas, xField, yField, run) {
    canvas.addEventListener('click', (e) => {
      const rect = canvas.getBoundingClientRect();
      const col = Math.floor((e.clientX - rect.left) * canvas.width / rect.width);
      const row = Math.floor((e.clientY - rect.top) * canvas.height / rect.height);
      // Pixels count from the bottom, as -p and the render loop do.
      $(xField).value = Math.min(canvas.width - 1, Math.max(0, col));
      $(yField).value = Math.min(canvas.height - 1, Math.max(0, canvas.height - 1 - row));
      run();
    });
  }
  pickPixel($('dbg-pick'), 'dbg-x', 'dbg-y', () => runPath());
  pickPixel($('dbg-bpick'), 'dbg-bx', 'dbg-by', () => runBsdf());

  const runIntersect = () => { state.lastInput = intersectInput(); return call('intersect', state.lastInput); };
  const runLights = () => { defaults(); return call('lights', lightsInput()); };
  const runPath = () => { limits(); return call('path', pathInput()); };
  const runBsdf = () => call('bsdf', {x: parseNum($('dbg-bx').value), y: parseNum($('dbg-by').value),
                                      samples: parseNum($('dbg-bsamples').value), seed: parseNum($('dbg-bseed').value)});
  const runEnvmap = () => call('envmap', {});
  $('dbg-intersect-run').addEventListener('click', runIntersect);
  $('dbg-lights-run').addEventListener('click', runLights);
  $('dbg-path-run').addEventListener('click', runPath);
  $('dbg-bsdf-run').addEventListener('click', runBsdf);
  $('dbg-envmap-run').addEventListener('click', runEnvmap);
  $('dbg-shape').addEventListener('change', () => {
    for (const e of document.querySelectorAll('[data-shape]')) e.hidden = e.dataset.shape !== $('dbg-shape').value;
  });
  for (const b of document.querySelectorAll('#debug-tabs button')) b.addEventListener('click', () => showTool(b.dataset.tool));

  // Starting values from the scene: its lights, a point just above the
  // middle of its floor (the intersection tester starts on a typed example).
  function defaults() {
    const sc = viewer.scene;
    if (!sc || state.defaultsFor === viewer.settings.scene) return;
    state.defaultsFor = viewer.settings.scene;
    const c = scale(add(sc.bounds.lo, sc.bounds.hi), 0.5);
    const v3 = (a) => a.map((x) => f(x)).join(', ');
    $('dbg-lpoint').value = v3([c[0], sc.bounds.lo[1] + 1e-3 * sceneSize(), c[2]]);
    const light = $('dbg-light');
    light.innerHTML = '';
    for (let i = 0; i < sc.lights; ++i) light.add(new Option(String(i), String(i)));
    $('dbg-primitive').max = sc.triangles + sc.spheres - 1;
  }
  function limits() {
    $('dbg-x').max = viewer.settings.width - 1;
    $('dbg-y').max = viewer.settings.height - 1;
    $('dbg-sample').max = viewer.settings.samples - 1;
    $('dbg-bx').max = viewer.settings.width - 1;
    $('dbg-by').max = viewer.settings.height - 1;
  }
  // New settings: what was drawn and listed was for the old ones.
  $('settings').addEventListener('change', () => {
    overlay.clear();
    overlay.redraw();
    state.last = {};
    for (const t of TOOLS) $(`dbg-${t}-out`).textContent = '';
  });

  return {
    show() {
      // The first time: step back from the render's camera, so that the
      // camera and the rays leaving it are in view.
      if (state.viewFor !== viewer.settings.scene) {
        state.viewFor = viewer.settings.scene;
        viewer.view3d.orbit(40, 15);
        viewer.view3d.zoom(3.2);
      }
      defaults();
      limits();
      copyRender();
      showTool(state.tool);
      document.body.dataset.debugReady = '1';
    },
    call, runIntersect, runLights, runPath, runBsdf, runEnvmap, showTool, overlay,
  };
}
