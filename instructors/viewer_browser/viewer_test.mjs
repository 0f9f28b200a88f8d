// The viewer's browser tests: each case starts a viewer (or the test build
// with planted faults), drives the real page in headless Chromium through
// playwright-core, and checks what the page shows against the command line.
//
//   node viewer_test.mjs --case NAME --viewer BIN --planted BIN --pathtracer BIN
//                        --scenes DIR --web DIR --out DIR
//
// Cases: page_render, camera_round_trip, bvh, bvh_click, rate_overlay,
// token_and_paths, todo_banner, crash_reported, screenshots, debug_tools,
// debug_crash, debug_todo; `--measure` prints timings instead (not a test; `--measure bvh` only BVH mode's frames,
// `--frames N` of them, default 120; `late` is the share of frames over 20 ms).
// Every wait is on an event of the page or a process, never a fixed delay.
import {spawn, spawnSync} from 'node:child_process';
import {createRequire} from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const args = {};
for (let i = 2; i < process.argv.length; ++i) {
  const a = process.argv[i];
  if (a.startsWith('--')) {
    const next = process.argv[i + 1];
    args[a.slice(2)] = next === undefined || next.startsWith('--') ? true : (++i, next);
  }
}
const OUT = path.resolve(args.out || 'viewer-artifacts');
fs.mkdirSync(OUT, {recursive: true});

let failures = 0, passes = 0;
function check(ok, what, detail) {
  if (ok) {
    ++passes;
    console.log(`ok - ${what}`);
  } else {
    ++failures;
    console.log(`FAIL - ${what}${detail ? `: ${detail}` : ''}`);
  }
  return ok;
}

function loadPlaywright() {
  const pkg = path.resolve(args.web, 'package.json');
  if (!fs.existsSync(path.join(args.web, 'node_modules', 'playwright-core'))) {
    console.log(`FAIL - playwright-core is not installed in ${args.web}/node_modules: run scripts/setup.sh (npm ci)`);
    process.exit(1);
  }
  return createRequire(pkg)('playwright-core');
}

// ------------------------------------------------------------- processes

const children = [];
process.on('exit', () => { for (const c of children) if (c.exitCode === null) c.kill('SIGKILL'); });

// Starts a viewer; resolves with {url, base, token, proc} once it printed its URL.
function startViewer(bin, flags, env) {
  return new Promise((resolve, reject) => {
    const proc = spawn(bin, flags, {env: Object.assign({}, process.env, env || {}), stdio: ['ignore', 'pipe', 'pipe']});
    children.push(proc);
    let out = '', err = '';
    proc.stderr.on('data', (d) => { err += d; });
    proc.stdout.on('data', (d) => {
      out += d;
      const line = out.split('\n')[0];
      if (out.includes('\n')) {
        const m = /^(http:\/\/127\.0\.0\.1:\d+)\/\?token=([0-9a-f]{32})$/.exec(line);
        if (m) resolve({url: line, base: m[1], token: m[2], proc, stderr: () => err});
        else reject(new Error(`unexpected first line: ${line}`));
      }
    });
    proc.on('exit', (code) => reject(new Error(`viewer exited (${code}) before printing its URL: ${err}`)));
  });
}

function stopViewer(v) {
  return new Promise((resolve) => {
    if (v.proc.exitCode !== null) return resolve(v.proc.exitCode);
    v.proc.on('exit', (code, sig) => resolve(code === null ? sig : code));
    v.proc.kill('SIGINT');
  });
}

function runCli(flags) {
  const r = spawnSync(args.pathtracer, flags, {encoding: 'utf8'});
  if (r.status !== 0) throw new Error(`pathtracer ${flags.join(' ')} failed: ${r.stderr}`);
  return r;
}

// ---------------------------------------------------------------- browser

async function openBrowser() {
  const {chromium} = loadPlaywright();
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'pt-viewer-chromium-'));
  // A fresh profile (playwright passes it as --user-data-dir).
  const browser = await chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
    acceptDownloads: true,
    viewport: {width: 1400, height: 900},
  });
  const page = browser.pages()[0] || await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  return {browser, page, errors, close: async () => { await browser.close(); fs.rmSync(profile, {recursive: true, force: true}); }};
}

// Starts a viewer with `flags` (opts.bin: another build, default the
// viewer; opts.env: added to its environment), opens its page in a fresh
// headless Chromium, waits until the page is ready (opts.load === false:
// leaves the page blank, for the caller to time the load) and runs
// fn(page, v, errors): v is startViewer's, errors the page's script errors
// so far. Whatever fn does, the browser is closed and the viewer stopped.
async function withViewerPage(flags, fn, opts = {}) {
  const v = await startViewer(opts.bin || args.viewer, flags, opts.env);
  try {
    const b = await openBrowser();
    try {
      if (opts.load !== false) {
        await b.page.goto(v.url);
        await b.page.waitForFunction(() => document.body.dataset.ready === '1');
      }
      return await fn(b.page, v, b.errors);
    } finally {
      await b.close();
    }
  } finally {
    await stopViewer(v);
  }
}

// Waits until the page's event log has an event matching `pred` (a function
// source over the event `e`) and returns it.
async function waitEvent(page, pred, timeout = 60000) {
  const h = await page.waitForFunction(`window.viewer && window.viewer.events.find((e) => ${pred})`, null, {timeout});
  return h.jsonValue();
}
const lastJob = (page) => page.evaluate(() => window.viewer.job);

async function renderEnd(page, job, timeout) {
  return waitEvent(page, `e.type === 'end' && e.job === ${job}`, timeout);
}

// The render canvas's pixels, as an array of RGBA bytes.
function canvasPixels(page) {
  return page.evaluate(() => {
    const c = document.getElementById('render-canvas');
    return Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data);
  });
}

// A PNG's pixels as the browser decodes it.
function pngPixels(page, file) {
  const b64 = fs.readFileSync(file).toString('base64');
  return page.evaluate(async (data) => {
    const img = new Image();
    img.src = `data:image/png;base64,${data}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    return {w: img.width, h: img.height, data: Array.from(g.getImageData(0, 0, img.width, img.height).data)};
  }, b64);
}

async function fetchBytes(v, p) {
  const res = await fetch(`${v.base}${p}`, {headers: {'X-Token': v.token}});
  if (!res.ok) throw new Error(`${p}: HTTP ${res.status}`);
  return Buffer.from(await res.arrayBuffer());
}

function sameArrays(a, b) {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; ++i) if (a[i] !== b[i]) return false;
  return true;
}

const SCENE = () => path.join(args.scenes, 'CBspheres_lambertian.dae');
// Small and quick, with every part's code in the loop (part 5, two bounces).
const FLAGS = ['-r', '96', '72', '-s', '16', '-l', '1', '-m', '2', '-t', '2', '--seed', '5'];

// ------------------------------------------------------------------ cases

const cases = {};

// The page loads, renders progressively to 16 samples and then shows
// exactly the command line's image; a settings change restarts the render;
// a cell render changes only its cell.
cases.page_render = async () => {
  await withViewerPage([...FLAGS, SCENE()], async (page, v, errors) => {
    const job = await lastJob(page);
    const end = await renderEnd(page, job);
    check(end.state === 'done' && end.samples === 16, 'the progressive render reaches 16 samples', JSON.stringify(end));
    const frames = await page.evaluate((j) => window.viewer.events.filter((e) => e.type === 'frame' && e.job === j)
      .map((e) => e.samples), job);
    check(JSON.stringify(end.passes) === '[1,2,4,8,16]', 'the render refines pass by pass: 1, 2, 4, 8, 16 samples per pixel',
          JSON.stringify(end.passes));
    // The page shows the newest pass when it asks (a pass that a faster one
    // overtook is skipped), the last one always.
    check(frames.length >= 1 && frames.every((n, i) => i === 0 || n > frames[i - 1]) && frames[frames.length - 1] === 16,
          'the page shows the passes in order, ending with the 16-sample one', JSON.stringify(frames));
    await page.screenshot({path: path.join(OUT, 'render_mode.png')});

    const cliPng = path.join(OUT, 'cli_render.png');
    runCli([...FLAGS, '-f', cliPng, SCENE()]);
    const served = await fetchBytes(v, `/api/png?job=${job}`);
    check(Buffer.compare(served, fs.readFileSync(cliPng)) === 0,
          'Save PNG gives the bytes of the command line\'s PNG at the same settings and seed');
    const shown = await canvasPixels(page), cli = await pngPixels(page, cliPng);
    check(cli.w === 96 && cli.h === 72 && sameArrays(shown, cli.data),
          'the page shows the command line\'s pixels after tone mapping');
    const pfm = await fetchBytes(v, `/api/pfm?job=${job}`);
    check(pfm.subarray(0, 3).toString() === 'PF\n' && pfm.length > 96 * 72 * 12, 'Save PFM gives a colour PFM');

    // A settings change restarts.
    await page.fill('input[name=samples]', '4');
    await page.dispatchEvent('input[name=samples]', 'change');
    const restarted = await waitEvent(page, `e.type === 'render' && e.job > ${job}`);
    check(restarted.settings.samples === 4, 'changing samples per pixel restarts the render at the new count',
          JSON.stringify(restarted.settings.samples));
    const end4 = await renderEnd(page, restarted.job);
    check(end4.state === 'done' && end4.samples === 4, 'the restarted render finishes at 4 samples', JSON.stringify(end4));
    // The keyboard: ] doubles the samples (keys act outside the form's fields).
    await page.evaluate(() => document.activeElement.blur());
    await page.keyboard.press(']');
    const keyed = await waitEvent(page, `e.type === 'render' && e.job > ${restarted.job}`);
    check(keyed.settings.samples === 8, '] doubles the samples and restarts', String(keyed.settings.samples));
    await renderEnd(page, keyed.job);

    // A cell render (dragged on the image) changes only the cell: it uses
    // another seed, so every pixel inside it gets new samples.
    const before = await canvasPixels(page);
    await page.evaluate(() => { window.viewer.settings.seed = 99; });
    await page.check('#cell-mode');
    const box = await page.locator('#render-canvas').boundingBox();
    const sx = box.width / 96, sy = box.height / 72;
    await page.mouse.move(box.x + 20.5 * sx, box.y + 10.5 * sy);
    await page.mouse.down();
    await page.mouse.move(box.x + 50.5 * sx, box.y + 40.5 * sy, {steps: 4});
    await page.mouse.up();
    const cellJob = await waitEvent(page, `e.type === 'render' && e.job > ${keyed.job}`);
    check(JSON.stringify(cellJob.cell) === JSON.stringify([20, 72 - 41, 31, 31]),
          'the dragged rectangle becomes the cell (-p counts rows from the bottom)', JSON.stringify(cellJob.cell));
    const cellEnd = await renderEnd(page, cellJob.job);
    check(cellEnd.state === 'done', 'the cell render finishes');
    const after = await canvasPixels(page);
    let outsideChanged = 0, insideChanged = 0;
    for (let y = 0; y < 72; ++y) {
      for (let x = 0; x < 96; ++x) {
        const i = 4 * (y * 96 + x);
        const changed = before[i] !== after[i] || before[i + 1] !== after[i + 1] || before[i + 2] !== after[i + 2];
        const inside = x >= 20 && x <= 50 && y >= 10 && y <= 40;
        if (changed && inside) ++insideChanged;
        if (changed && !inside) ++outsideChanged;
      }
    }
    check(outsideChanged === 0, 'a cell render leaves every pixel outside the cell unchanged', `${outsideChanged} changed`);
    check(insideChanged > 31 * 31 / 2, 'a cell render redraws the cell', `${insideChanged} of 961 changed`);
    await page.screenshot({path: path.join(OUT, 'cell_render.png')});

    // Overlays: the tests-per-ray heat map and the rate image are drawn.
    await page.selectOption('#overlay', 'tests');
    await page.waitForFunction(() => document.getElementById('hud').dataset.scale !== undefined);
    const scale = await page.evaluate(() => Number(document.getElementById('hud').dataset.scale));
    check(scale > 0, 'the tests-per-ray overlay has a scale (the most tests per ray of any pixel)', String(scale));
    await page.screenshot({path: path.join(OUT, 'overlay_tests.png')});

    // The difference against the grader's reference of a case, by the
    // grader's own statistics: this build is the reference, so it matches.
    await page.click('#btn-whole');
    const beforeCase = await lastJob(page);
    await page.selectOption('#case', 'p1_spheres');
    await page.click('#btn-apply-case');
    const caseRender = await waitEvent(page, `e.type === 'render' && e.job > ${beforeCase} && e.settings.width === 320`);
    check(caseRender.settings.part === 1 && caseRender.settings.height === 240,
          'Use case settings renders with the case\'s settings (--part 1 -r 320 240)', JSON.stringify(caseRender.settings));
    const diff = await waitEvent(page, `e.type === 'diff' && e.job === ${caseRender.job}`);
    check(diff.summary && diff.summary.startsWith('matches the reference'),
          'the difference overlay scores the render against case p1_spheres\'s reference: it matches',
          JSON.stringify(diff));
    await page.screenshot({path: path.join(OUT, 'overlay_diff.png')});

    // The normals overlay is its own small job: it neither stops nor
    // replaces the render it is drawn over.
    await page.selectOption('#overlay', 'normals');
    const lastRender = await lastJob(page);
    await page.evaluate(() => document.activeElement.blur());
    await page.keyboard.press('r');
    const again = await waitEvent(page, `e.type === 'render' && e.job > ${lastRender}`);
    const againEnd = await renderEnd(page, again.job);
    check(againEnd.state === 'done', 'a render with the normals overlay runs to the end', againEnd.state);
    await page.waitForFunction(() => document.getElementById('overlay-note').textContent.startsWith('normals'));
    const normalsDrawn = await page.evaluate(() => {
      const c = document.getElementById('overlay-canvas');
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let n = 0;
      for (let i = 3; i < d.length; i += 4) n += d[i] > 0;
      return n / (d.length / 4);
    });
    check(normalsDrawn > 0.99, 'the normals overlay covers the image', String(normalsDrawn));
    check(errors.length === 0, 'no script errors in the page', errors.join('; '));
  });
};

// "Save camera" writes the course's -c file of the 3D view; the command
// line renders exactly the viewer's "render from here" image from it.
cases.camera_round_trip = async () => {
  const flags = ['-r', '80', '60', '-s', '4', '-m', '1', '-t', '2', '--seed', '3'];
  await withViewerPage([...flags, SCENE()], async (page, v, errors) => {
    const first = await renderEnd(page, await lastJob(page));
    check(first.state === 'done', 'the first render finishes');
    const defaultPng = await fetchBytes(v, `/api/png?job=${first.job}`);
    await page.keyboard.press('e');
    await page.waitForFunction(() => document.body.dataset.view3d === 'camera', null, {timeout: 60000});
    // Orbit and zoom with the mouse.
    const box = await page.locator('#three-canvas').boundingBox();
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    await page.mouse.down();
    await page.mouse.move(box.x + box.width / 2 + 60, box.y + box.height / 2 + 25, {steps: 5});
    await page.mouse.up();
    await page.mouse.wheel(0, -200);
    await page.screenshot({path: path.join(OUT, 'camera_mode.png')});
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('#btn-save-camera')]);
    const camFile = path.join(OUT, 'camera.txt');
    await download.saveAs(camFile);
    const lines = fs.readFileSync(camFile, 'utf8').trim().split('\n');
    check(lines.length === 6 && lines.map((l) => l.trim().split(/\s+/).length).join() === '5,6,5,9,3,2',
          'the saved camera file has the course\'s six lines', lines.join(' | '));
    await page.click('#btn-render-here');
    const here = await waitEvent(page, `e.type === 'render' && e.job > ${first.job}`);
    const hereEnd = await renderEnd(page, here.job);
    check(hereEnd.state === 'done', 'the render from the new view finishes');
    const viewerPng = await fetchBytes(v, `/api/png?job=${here.job}`);
    const cliPng = path.join(OUT, 'camera_cli.png');
    runCli([...flags, '-c', camFile, '-f', cliPng, SCENE()]);
    check(Buffer.compare(viewerPng, fs.readFileSync(cliPng)) === 0,
          'pathtracer -c <saved camera> renders the viewer\'s image exactly');
    check(Buffer.compare(viewerPng, defaultPng) !== 0, 'the orbited view differs from the scene\'s own view');
    check(errors.length === 0, 'no script errors in the page', errors.join('; '));
  });
};

// BVH mode: the root's box is the scene's bounds; a child's box is smaller.
cases.bvh = async () => {
  await withViewerPage(['-r', '80', '60', '-s', '1', '-t', '2', path.join(args.scenes, 'CBbunny.dae')], async (page, v, errors) => {
    await page.keyboard.press('v');
    await page.waitForFunction(() => document.body.dataset.bvhNode === '0', null, {timeout: 60000});
    const r = await page.evaluate(() => ({root: window.viewer.view3d.box(0), bounds: window.viewer.scene.bounds}));
    const f = (xs) => xs.map((x) => Math.fround(x));
    check(JSON.stringify(r.root.lo) === JSON.stringify(f(r.bounds.lo)) &&
          JSON.stringify(r.root.hi) === JSON.stringify(f(r.bounds.hi)),
          'the root node\'s box is the scene\'s bounds', JSON.stringify(r));
    const info = await page.locator('#bvh-info').textContent();
    check(/depth 0/.test(info) && /primitives [\d,]+/.test(info) && /SAH cost \d/.test(info) && /camera rays in [\d,]+/.test(info),
          'the panel shows depth, primitives, SAH cost and rays for the root', info);
    await page.screenshot({path: path.join(OUT, 'bvh_mode.png')});
    // Step to each child with the course's keys and back with '?'.
    const kids = [];
    for (const key of ['<', '>']) {
      await page.keyboard.press(key);
      await page.waitForFunction(() => document.body.dataset.bvhNode !== '0');
      kids.push(await page.evaluate(() => {
        const v = window.viewer.view3d;
        return Object.assign(v.nodeInfo(v.state.node), {text: document.getElementById('bvh-info').textContent});
      }));
      await page.keyboard.press('?');
      await page.waitForFunction(() => document.body.dataset.bvhNode === '0');
    }
    const root = await page.evaluate(() => window.viewer.view3d.nodeInfo(0));
    const vol = (x) => [0, 1, 2].reduce((p, k) => p * (x.hi[k] - x.lo[k]), 1);
    const within = (c) => [0, 1, 2].every((k) => c.box.lo[k] >= root.box.lo[k] && c.box.hi[k] <= root.box.hi[k]);
    check(kids.every(within), 'both children\'s boxes lie inside the root\'s', JSON.stringify(kids.map((k) => k.box)));
    check(kids.some((k) => vol(k.box) < vol(root.box)), 'stepping to a child shrinks the box',
          JSON.stringify({root: root.box, kids: kids.map((k) => k.box)}));
    check(kids[0].primitives + kids[1].primitives === root.primitives && kids.every((k) => k.primitives < root.primitives),
          'the children split the root\'s primitives between them',
          `${kids[0].primitives} + ${kids[1].primitives} of ${root.primitives}`);
    check(kids.every((k) => k.depth === 1 && /depth 1 of/.test(k.text)), 'the panel shows the children at depth 1');
    check(kids.every((k) => k.rays <= root.rays), 'no child is entered by more camera rays than the root',
          `${kids.map((k) => k.rays)} vs ${root.rays}`);
    await page.fill('#depth-slider', '3');
    await page.dispatchEvent('#depth-slider', 'input');
    check((await page.locator('#depth-label').textContent()) === '3', 'the depth slider shows depth 3');
    await page.screenshot({path: path.join(OUT, 'bvh_depth.png')});
    check(errors.length === 0, 'no script errors in the page', errors.join('; '));
  });
};

// Convex hull of points {x, y} (monotone chain), counter-clockwise in a
// y-up frame.
function hull(pts) {
  const p = pts.slice().sort((a, c) => a.x - c.x || a.y - c.y);
  const cross = (o, a, c) => (a.x - o.x) * (c.y - o.y) - (a.y - o.y) * (c.x - o.x);
  const half = (list) => {
    const h = [];
    for (const q of list) {
      while (h.length >= 2 && cross(h[h.length - 2], h[h.length - 1], q) <= 0) h.pop();
      h.push(q);
    }
    h.pop();
    return h;
  };
  return half(p).concat(half(p.slice().reverse()));
}

// Signed distance from (x, y) to a convex polygon's boundary: positive
// inside, negative outside (the polygon counter-clockwise, as hull gives it).
function polygonDepth(poly, x, y) {
  let inside = true, d = Infinity;
  for (let i = 0; i < poly.length; ++i) {
    const a = poly[i], c = poly[(i + 1) % poly.length];
    const ex = c.x - a.x, ey = c.y - a.y, len = Math.hypot(ex, ey);
    if ((ex * (y - a.y) - ey * (x - a.x)) / len < 0) inside = false;
    const t = Math.max(0, Math.min(1, ((x - a.x) * ex + (y - a.y) * ey) / (len * len)));
    d = Math.min(d, Math.hypot(x - a.x - t * ex, y - a.y - t * ey));
  }
  return inside ? d : -d;
}

// BVH mode, clicking. A click inside one child's box on screen (and
// outside the other's) descends into that child, as its key does; a click
// on empty space changes nothing; a click does not move the camera. The
// node is the first one, breadth first, whose children both have a part of
// the screen to themselves (at the root of a Cornell box one child's box
// holds the other's, checked last: there the inner box takes a click
// inside both).
cases.bvh_click = async () => {
  const flags = ['-r', '480', '360', '-s', '1', '-m', '1', '-t', '2', path.join(args.scenes, 'CBbunny.dae')];
  await withViewerPage(flags, async (page, v, errors) => {
    await page.keyboard.press('v');
    await page.waitForFunction(() => document.body.dataset.bvhNode === '0', null, {timeout: 60000});
    const node = () => page.evaluate(() => Number(document.body.dataset.bvhNode));
    const here = () => page.evaluate(() => {
      const v3 = window.viewer.view3d;
      return Object.assign(v3.nodeInfo(v3.state.node), {node: v3.state.node, text: document.getElementById('bvh-info').textContent});
    });
    const press = async (key) => {
      const before = await node();
      await page.keyboard.press(key);
      await page.waitForFunction((n) => document.body.dataset.bvhNode !== String(n), before);
    };
    // Walks from the root along keys ('<', '>').
    const goTo = async (keys) => {
      while (await node() !== 0) await press('?');
      for (const k of keys) await press(k);
      return here();
    };
    // Each child's box projected by the page's own camera (three.js's
    // project: the matrices it draws with) into page coordinates, and a
    // 4-pixel grid over the canvas.
    const project = (nodes) => page.evaluate((ks) => {
      const v3 = window.viewer.view3d, cam = v3.three.camera, canvas = document.getElementById('three-canvas');
      cam.updateMatrixWorld();
      const r = canvas.getBoundingClientRect();
      const corners = ks.map((k) => {
        const b = v3.box(k), out = [];
        for (let c = 0; c < 8; ++c) {
          const p = cam.position.clone().set(c & 1 ? b.hi[0] : b.lo[0], c & 2 ? b.hi[1] : b.lo[1],
                                             c & 4 ? b.hi[2] : b.lo[2]).project(cam);
          out.push({x: r.left + (p.x + 1) / 2 * r.width, y: r.top + (1 - p.y) / 2 * r.height, z: p.z});
        }
        return out;
      });
      return {corners, rect: {left: r.left, top: r.top, right: r.right, bottom: r.bottom}, view: v3.view()};
    }, nodes).then((g) => {
      const r = g.rect, grid = [];
      for (let y = r.top + 2; y < r.bottom - 2; y += 4) for (let x = r.left + 2; x < r.right - 2; x += 4) grid.push({x, y});
      return Object.assign(g, {grid, centre: {x: (r.left + r.right) / 2, y: (r.top + r.bottom) / 2}});
    });
    // The grid point with the best score of at least 3 (pixels) where the
    // canvas is on top (not the panel over it), or null.
    const pick = async (grid, score) => {
      const ranked = grid.map((p) => ({x: p.x, y: p.y, s: score(p)})).filter((p) => p.s >= 3).sort((a, c) => c.s - a.s);
      for (let i = 0; i < ranked.length; i += 256) {
        const hit = await page.evaluate((ps) => ps.find((p) => document.elementFromPoint(p.x, p.y) ===
                                                             document.getElementById('three-canvas')), ranked.slice(i, i + 256));
        if (hit) return hit;
      }
      return null;
    };

    // Breadth first over the top four levels, by the keys.
    let found = null;
    const queue = [[]];
    while (queue.length && !found) {
      const keys = queue.shift();
      const at = await goTo(keys);
      if (/\(leaf\)/.test(at.text) || keys.length > 3) continue;
      const kids = [];
      for (const k of ['<', '>']) {
        await press(k);
        kids.push(await here());
        await press('?');
      }
      const geo = await project(kids.map((k) => k.node));
      if (!geo.corners.flat().every((p) => p.z > -1 && p.z < 1)) continue;
      // Page y grows downwards: flipped for the hull's orientation.
      const polys = geo.corners.map((cs) => hull(cs.map((p) => ({x: p.x, y: -p.y}))));
      const depth = (i, p) => polygonDepth(polys[i], p.x, -p.y);
      // Deepest inside child i's outline and 3 pixels or more outside the
      // other's; empty space: the point nearest the view's centre that is
      // 10 pixels or more outside both.
      const only = [await pick(geo.grid, (p) => Math.min(depth(0, p), -depth(1, p))),
                    await pick(geo.grid, (p) => Math.min(depth(1, p), -depth(0, p)))];
      const empty = await pick(geo.grid, (p) => (Math.min(-depth(0, p), -depth(1, p)) >= 10 ?
        1e6 - Math.hypot(p.x - geo.centre.x, p.y - geo.centre.y) : 0));
      if (only[0] && only[1] && empty) found = {keys, at, kids, only, empty, view: geo.view};
      queue.push([...keys, '<'], [...keys, '>']);
    }
    check(found !== null, 'a node near the root has two children each with a part of the screen to itself');
    if (!found) return;
    const {at, kids, only, empty} = found;
    console.log(`# node ${at.node} (keys ${found.keys.join(' ') || 'none'}), children ${kids.map((k) => k.node).join(', ')}`);
    await goTo(found.keys);
    // The picture: the node, its children's boxes, and where the clicks go
    // (marks drawn over the page for the screenshot only).
    const marks = (on) => page.evaluate(({pts, show}) => {
      for (const m of document.querySelectorAll('.test-click-mark')) m.remove();
      if (!show) return;
      for (const [x, y, colour] of pts) {
        const m = document.createElement('div');
        m.className = 'test-click-mark';
        m.style.cssText = `position: fixed; left: ${x - 6}px; top: ${y - 6}px; width: 8px; height: 8px; ` +
                          `border: 2px solid ${colour}; border-radius: 50%; pointer-events: none; z-index: 9`;
        document.body.appendChild(m);
      }
    }, {pts: [[empty.x, empty.y, '#fff'], [only[0].x, only[0].y, '#ff4d4d'], [only[1].x, only[1].y, '#4da6ff']], show: on});
    await marks(true);
    await page.screenshot({path: path.join(OUT, 'bvh_click_points.png')});
    await marks(false);

    // Each click's outcome, read by a listener that runs after the page's own.
    await page.evaluate(() => {
      window.clicksSeen = [];
      window.addEventListener('mouseup', () => window.clicksSeen.push({
        node: document.body.dataset.bvhNode, text: document.getElementById('bvh-info').textContent,
        box: window.viewer.view3d.box(window.viewer.view3d.state.node), view: window.viewer.view3d.view(),
      }));
    });
    const click = async (p) => {
      const n = await page.evaluate(() => window.clicksSeen.length);
      await page.mouse.click(p.x, p.y);
      await page.waitForFunction((k) => window.clicksSeen.length > k, n);
      return page.evaluate(() => window.clicksSeen.at(-1));
    };
    const e = await click(empty);
    check(e.node === String(at.node) && e.text === at.text, `a click on empty space leaves node ${at.node} selected`,
          `node ${e.node} after a click at (${empty.x}, ${empty.y})`);
    check(JSON.stringify(e.view) === JSON.stringify(found.view), 'a click does not move the camera', JSON.stringify(e.view));
    await goTo(found.keys);
    const side = ['left', 'right'];
    for (const i of [0, 1]) {
      const k = kids[i];
      const c = await click(only[i]);
      check(c.node === String(k.node) && c.text === k.text,
            `a click inside the ${side[i]} child's box selects it: node ${k.node}, its panel (${k.primitives} primitives)`,
            `node ${c.node} after a click at (${only[i].x}, ${only[i].y}), panel: ${JSON.stringify(c.text)}`);
      check(JSON.stringify(c.box) === JSON.stringify(k.box), `the current box is then the ${side[i]} child's`,
            JSON.stringify({shown: c.box, child: k.box}));
      await page.screenshot({path: path.join(OUT, `bvh_click_${side[i]}.png`)});
      await goTo(found.keys);
    }

    // At the root one child's box holds the other's (the walls' box holds
    // the bunny's): a click inside the inner one's outline selects it,
    // though the ray enters the outer box first.
    await goTo([]);
    const rootKids = [];
    for (const k of ['<', '>']) {
      await press(k);
      rootKids.push(await here());
      await press('?');
    }
    const holds = (a, b) => [0, 1, 2].every((k) => a.box.lo[k] <= b.box.lo[k] && b.box.hi[k] <= a.box.hi[k]);
    const inner = holds(rootKids[0], rootKids[1]) ? 1 : holds(rootKids[1], rootKids[0]) ? 0 : -1;
    check(inner >= 0, 'at the root of CBbunny one child\'s box holds the other\'s',
          JSON.stringify(rootKids.map((k) => k.box)));
    if (inner >= 0) {
      const geo = await project(rootKids.map((k) => k.node));
      const poly = hull(geo.corners[inner].map((p) => ({x: p.x, y: -p.y})));
      const spot = await pick(geo.grid, (p) => polygonDepth(poly, p.x, -p.y));
      check(spot !== null, 'the inner child\'s box has a part of the screen');
      if (spot) {
        const c = await click(spot);
        check(c.node === String(rootKids[inner].node),
              `a click inside the inner (${side[inner]}) child's box, which the outer one also covers, selects it: node ${rootKids[inner].node}`,
              `node ${c.node} after a click at (${spot.x}, ${spot.y})`);
        await page.screenshot({path: path.join(OUT, 'bvh_click_inner.png')});
      }
    }
    check(errors.length === 0, 'no script errors in the page', errors.join('; '));
  });
};

// The course's rate colour of a rate in [0, 1] (blue 0, green 1/2, red 1),
// as 8-bit RGB.
function rateColour(r) {
  const c = r < 0.5 ? [0, r / 0.5, 1 - r / 0.5] : [(r - 0.5) / 0.5, 1 - (r - 0.5) / 0.5, 0];
  return c.map((x) => Math.round(255 * Math.fround(x)));
}

// The overlay canvas's pixels, as an array of RGBA bytes.
function overlayPixels(page) {
  return page.evaluate(() => {
    const c = document.getElementById('overlay-canvas');
    return Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data);
  });
}

// Part 5's sample-rate overlay: after an adaptive render (-a 8 0.1: some
// pixels stop after 8, 16, ... of their 64 samples) it shows exactly the
// rate image the command line writes (_rate.png) at the same settings and
// seed; its colours are the legend's, blue for pixels that stopped early,
// red for those that took every sample; and with the overlay on, a
// restarted render's overlay is the new render's.
cases.rate_overlay = async () => {
  const flags = ['-r', '64', '48', '-s', '64', '-a', '8', '0.1', '-l', '2', '-m', '2', '-t', '2'];
  const cliRate = (seed) => {
    const png = path.join(OUT, `cli_seed${seed}.png`);
    runCli([...flags, '--seed', String(seed), '-f', png, SCENE()]);
    return png.replace(/\.png$/, '_rate.png');
  };
  await withViewerPage([...flags, '--seed', '5', SCENE()], async (page, v, errors) => {
    const end = await renderEnd(page, await lastJob(page));
    check(end.state === 'done' && end.samples === 64, 'the adaptive render finishes at 64 samples per pixel', JSON.stringify(end));
    await page.selectOption('#overlay', 'rate');
    await page.waitForFunction(() => document.getElementById('overlay-note').textContent.startsWith('samples taken'));
    const shown = await overlayPixels(page), cli = await pngPixels(page, cliRate(5));
    check(cli.w === 64 && cli.h === 48 && sameArrays(shown, cli.data),
          'the sample-rate overlay shows the command line\'s rate image (_rate.png) pixel for pixel');
    // The legend: every pixel took a whole number of 8-sample batches, so
    // its colour is the rate colour of k/8 for k = 1..8.
    const legend = new Map([1, 2, 3, 4, 5, 6, 7, 8].map((k) => [rateColour(k / 8).join(), k]));
    const batches = [];
    for (let i = 0; i < shown.length; i += 4) batches.push(legend.get(shown.slice(i, i + 3).join()));
    check(batches.every((k) => k !== undefined), 'every pixel has the colour of 8, 16, ... or 64 samples taken of 64',
          JSON.stringify(shown.slice(0, 12)));
    const count = (pred) => batches.filter(pred).length;
    check(count((k) => k === 8) > 0 && count((k) => k <= 2) > 0,
          'some pixels took every sample (red) and some stopped within two batches (blue-green)',
          `${count((k) => k === 8)} red, ${count((k) => k <= 2)} at 8 or 16 samples`);
    await page.screenshot({path: path.join(OUT, 'overlay_rate.png')});

    // With the overlay on, a new seed restarts the render; the overlay is
    // redrawn with each pass and ends as the new render's rate image.
    await page.fill('input[name=seed]', '6');
    await page.dispatchEvent('input[name=seed]', 'change');
    const next = await waitEvent(page, `e.type === 'render' && e.job > ${end.job}`);
    const nextEnd = await renderEnd(page, next.job);
    check(nextEnd.state === 'done' && next.settings.seed === 6, 'the render restarts with seed 6 and finishes',
          JSON.stringify(next.settings.seed));
    const again = await overlayPixels(page), cli6 = await pngPixels(page, cliRate(6));
    check(sameArrays(again, cli6.data) && !sameArrays(again, shown),
          'the overlay then shows the new render\'s rate image (the command line\'s at --seed 6), not the old one');
    check(errors.length === 0, 'no script errors in the page', errors.join('; '));
  });
};

// Requests without the token are refused; files outside the folders named
// on the command line cannot be opened; bad requests get a 4xx.
cases.token_and_paths = async () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'pt-viewer-paths-'));
  const outside = fs.mkdtempSync(path.join(os.tmpdir(), 'pt-viewer-outside-'));
  fs.copyFileSync(SCENE(), path.join(dir, 'scene.dae'));
  fs.copyFileSync(SCENE(), path.join(outside, 'secret.dae'));
  fs.symlinkSync(path.join(outside, 'secret.dae'), path.join(dir, 'link.dae'));
  const v = await startViewer(args.viewer, ['-r', '32', '24', path.join(dir, 'scene.dae')]);
  try {
    for (const p of ['/', '/api/state', '/web/app.js', '/three/three.module.js', '/api/status?job=1']) {
      const res = await fetch(`${v.base}${p}`);
      check(res.status === 403, `${p} without the token is refused (403)`, String(res.status));
    }
    const wrong = await fetch(`${v.base}/api/state?token=${'0'.repeat(32)}`);
    check(wrong.status === 403, 'a wrong token is refused (403)', String(wrong.status));
    const ok = await fetch(`${v.base}/api/state?token=${v.token}`);
    check(ok.status === 200, 'the token of the printed URL is accepted', String(ok.status));
    const post = (body) => fetch(`${v.base}/api/render`, {method: 'POST', headers: {'X-Token': v.token}, body});
    for (const [what, scene] of [['a path with ..', `${dir}/../${path.basename(outside)}/secret.dae`],
                                 ['an absolute path elsewhere', path.join(outside, 'secret.dae')],
                                 ['/etc/passwd', '/etc/passwd'],
                                 ['a symlink out of the folder', path.join(dir, 'link.dae')]]) {
      const res = await post(JSON.stringify({scene}));
      const body = await res.json();
      check(res.status === 403 && /outside the folders/.test(body.error), `${what} is refused`, `${res.status} ${body.error}`);
    }
    for (const [what, body, status] of [['malformed JSON', '{"samples": ', 400],
                                        ['negative samples', '{"samples": -4}', 400],
                                        ['an absurd size', '{"width": 100000, "height": 100000}', 400],
                                        ['a fractional count', '{"threads": 1.5}', 400],
                                        ['a cell outside the image', '{"cell": [30, 0, 10, 10]}', 400],
                                        ['a body of a megabyte', `{"scene": "${'x'.repeat(1 << 20)}"}`, 413]]) {
      const res = await post(body);
      check(res.status === status, `${what} gets ${status}`, String(res.status));
    }
    const alive = await fetch(`${v.base}/api/state?token=${v.token}`);
    check(alive.status === 200, 'the server still serves after the bad requests');
  } finally {
    await stopViewer(v);
    fs.rmSync(dir, {recursive: true, force: true});
    fs.rmSync(outside, {recursive: true, force: true});
  }
};

// A build whose part prints a stub's TODO line: the page says which part
// and function, and still shows the image.
cases.todo_banner = async () => {
  await withViewerPage(['-r', '64', '48', '-s', '2', '-t', '2', SCENE()], async (page) => {
    const end = await renderEnd(page, await lastJob(page));
    const text = await page.locator('#banner').textContent();
    check(await page.locator('#banner').isVisible() &&
          text.includes('Part 1 not implemented (TODO: raytrace_pixel, stages/part1_raytracing/pixel_sampling.cpp)'),
          'the banner names the part, the function and the file', text);
    check(end.state === 'done', 'the render still finishes', end.state);
    const px = await canvasPixels(page);
    check(px.some((x, i) => i % 4 !== 3 && x > 0), 'the canvas is not blank');
    await page.screenshot({path: path.join(OUT, 'todo_banner.png')});
  }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'todo'}});
};

// A crash in a render (a planted null write) is reported in the page and
// the server keeps serving: the next render works.
cases.crash_reported = async () => {
  await withViewerPage(['-r', '64', '48', '-s', '2', '-t', '2', '--seed', '13', SCENE()], async (page, v) => {
    const end = await renderEnd(page, await lastJob(page));
    const text = await page.locator('#banner').textContent();
    check(end.state === 'crashed', 'the render is reported as crashed', end.state);
    check(text.includes('planted_crash_in_render crashed: SIGSEGV while rendering'),
          'the banner names the function and the signal', text);
    await page.screenshot({path: path.join(OUT, 'crash_banner.png')});
    await page.fill('input[name=seed]', '0');
    await page.dispatchEvent('input[name=seed]', 'change');
    const next = await waitEvent(page, `e.type === 'render' && e.job > ${end.job}`);
    const nextEnd = await renderEnd(page, next.job);
    check(nextEnd.state === 'done', 'the server keeps serving: the next render finishes', nextEnd.state);
    check(!(await page.locator('#banner').isVisible()), 'the banner is gone with the crash');
    // An exception thrown in the middle of a render: its message, and the
    // server goes on.
    await page.fill('input[name=seed]', '14');
    await page.dispatchEvent('input[name=seed]', 'change');
    const thrower = await waitEvent(page, `e.type === 'render' && e.job > ${next.job}`);
    const thrown = await renderEnd(page, thrower.job);
    const thrownText = await page.locator('#banner').textContent();
    check(thrown.state === 'failed' && thrownText.includes('planted failure: a part threw an exception'),
          'an exception in a render is reported with its message', `${thrown.state}: ${thrownText}`);
    check(v.proc.exitCode === null, 'the server process is still running');
  }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'crash'}});
};

// One screenshot per mode at a realistic size (the README's pictures:
// --publish DIR copies them there), and the 3D views draw something.
cases.screenshots = async () => {
  const flags = ['-r', '480', '360', '-s', '16', '-l', '1', '-m', '3', '-t', '2', path.join(args.scenes, 'CBbunny.dae')];
  await withViewerPage(flags, async (page, v, errors) => {
    const shots = [];
    // PNG artefacts; the README's copies (--publish) as small JPEGs of the same frame.
    const shoot = async (name) => {
      const clip = {x: 0, y: 0, width: 1280, height: 860};
      await page.screenshot({path: path.join(OUT, name.replace(/\.jpg$/, '.png')), clip});
      if (args.publish) {
        const file = path.join(OUT, name);
        await page.screenshot({path: file, type: 'jpeg', quality: 82, clip});
        shots.push(file);
      }
    };
    // The WebGL canvas's pixels that are not the background.
    const drawn = () => page.evaluate(() => {
      const c = document.getElementById('three-canvas');
      const g = document.createElement('canvas');
      g.width = c.width;
      g.height = c.height;
      const x = g.getContext('2d');
      x.drawImage(c, 0, 0);
      const d = x.getImageData(0, 0, g.width, g.height).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4) if (Math.abs(d[i] - 0x15) + Math.abs(d[i + 1] - 0x16) + Math.abs(d[i + 2] - 0x1a) > 30) ++n;
      return n / (d.length / 4);
    });
    const end = await renderEnd(page, await lastJob(page));
    check(end.state === 'done', 'the render finishes');
    await shoot('render_mode.jpg');
    await page.selectOption('#overlay', 'tests');
    await page.waitForFunction(() => document.getElementById('hud').dataset.scale !== undefined);
    await shoot('render_overlay_tests.jpg');
    await page.selectOption('#overlay', '');
    await page.keyboard.press('e');
    await page.waitForFunction(() => document.body.dataset.view3d === 'camera', null, {timeout: 60000});
    const camDrawn = await drawn();
    check(camDrawn > 0.2, 'the camera view draws the scene (WebGL in headless Chromium)', String(camDrawn));
    await shoot('camera_mode.jpg');
    await page.keyboard.press('v');
    await page.waitForFunction(() => document.body.dataset.view3d === 'bvh' && document.body.dataset.bvhNode === '0',
                               null, {timeout: 60000});
    for (const k of ['<', '<']) {
      const before = await page.evaluate(() => document.body.dataset.bvhNode);
      await page.keyboard.press(k);
      await page.waitForFunction((n) => document.body.dataset.bvhNode !== n, before);
    }
    check(await drawn() > 0.2, 'the BVH view draws the scene and the boxes');
    await shoot('bvh_mode.jpg');
    await page.keyboard.press('?');
    await page.keyboard.press('?');
    await page.waitForFunction(() => document.body.dataset.bvhNode === '0');
    await page.fill('#depth-slider', '6');
    await page.dispatchEvent('#depth-slider', 'input');
    await shoot('bvh_depth.jpg');
    check(errors.length === 0, 'no script errors in the page', errors.join('; '));
    if (args.publish) {
      fs.mkdirSync(args.publish, {recursive: true});
      for (const f of shots) fs.copyFileSync(f, path.join(args.publish, path.basename(f)));
    }
  });
};

// Debug mode: the path inspector's total is the command line's pixel at
// -s 1 (sample 0 is the pixel), its 3D path starts at the camera; the
// intersection tester's t and normal for typed-in rays against known
// shapes; the light-sample tester's points lie on the light; absurd input
// is refused with a 4xx and a message, and the server keeps serving.
const DEBUG_FLAGS = ['-r', '120', '90', '-s', '1', '-l', '2', '-m', '4', '-t', '2', '--seed', '7'];

// A PFM's pixel (x, y), (0, 0) bottom-left.
function pfmPixel(buf, x, y) {
  let off = 0;
  for (let lines = 0; lines < 3; ++off) if (buf[off] === 0x0a) ++lines;
  const [w] = buf.subarray(3, off).toString().split(/\s+/).map(Number);
  const f = new Float32Array(buf.buffer.slice(buf.byteOffset + off, buf.byteOffset + buf.length));
  const i = 3 * (y * w + x);
  return [f[i], f[i + 1], f[i + 2]];
}

async function debugCall(page, tool, run) {
  const before = await page.evaluate((t) => window.viewer.events.filter((e) => e.type === 'debug' && e.tool === t).length, tool);
  await run();
  await page.waitForFunction(([t, n]) => window.viewer.events.filter((e) => e.type === 'debug' && e.tool === t).length > n,
                             [tool, before], {timeout: 120000});
  return page.evaluate((t) => window.viewer.events.filter((e) => e.type === 'debug' && e.tool === t).at(-1), tool);
}

async function openDebug(page) {
  await page.keyboard.press('d');
  await page.waitForFunction(() => document.body.dataset.debugReady === '1', null, {timeout: 60000});
}

cases.debug_tools = async () => {
  const pfmFile = path.join(OUT, 'cli.pfm');
  runCli([...DEBUG_FLAGS, '--pfm', pfmFile, '-f', path.join(OUT, 'cli.png'), SCENE()]);
  const cli = fs.readFileSync(pfmFile);
  await withViewerPage([...DEBUG_FLAGS, SCENE()], async (page, v, errors) => {
    // PNG artefacts; --publish DIR: the README's picture (a JPEG) of the path inspector.
    const shoot = async (name) => {
      const clip = {x: 0, y: 0, width: 1400, height: 900};
      await page.screenshot({path: path.join(OUT, name.replace(/\.jpg$/, '.png')), clip});
      if (args.publish && name.endsWith('.jpg')) {
        fs.mkdirSync(args.publish, {recursive: true});
        await page.screenshot({path: path.join(args.publish, name), type: 'jpeg', quality: 82, clip});
      }
    };
    const end = await renderEnd(page, await lastJob(page));
    check(end.state === 'done', 'the render finishes', end.state);
    await openDebug(page);
    await page.click('#debug-tabs button[data-tool=path]');

    // Path inspector: click a pixel of the render (a sphere, lit and bouncing).
    const [px, py] = [70, 38];  // (x, y) from the bottom
    const box = await page.locator('#dbg-pick').boundingBox();
    const entry = await debugCall(page, 'path', () =>
      page.mouse.click(box.x + (px + 0.5) * box.width / 120, box.y + (90 - py - 0.5) * box.height / 90));
    check(entry.ok && entry.status === 200, 'the path inspector answers', entry.error);
    const r = entry.result;
    check(r.pixel[0] === px && r.pixel[1] === py && r.sample === 0, 'the clicked pixel and sample 0 are traced',
          JSON.stringify(r.pixel));
    const want = pfmPixel(cli, px, py);
    const got = r.returned.map((x) => Math.fround(x));
    check(sameArrays(got, want), 'the total equals the command line\'s pixel (pathtracer --pfm at -s 1)',
          `${got} vs ${want}`);
    check(r.steps.length >= 2, 'the path has bounces', String(r.steps.length));
    const rows = await page.locator('#dbg-path-table tr[data-bounce]').count();
    check(rows === r.steps.length, 'the table lists every step', `${rows} rows, ${r.steps.length} steps`);
    const totalText = await page.locator('#dbg-path-total').textContent();
    let shown = totalText.replace(/[()]/g, '').split(',').map(Number);
    if (shown.length === 1) shown = [shown[0], shown[0], shown[0]];  // a grey: one number
    check(shown.length === 3 && shown.every((x, i) => Math.abs(x - want[i]) <= 1e-5 * Math.max(1, Math.abs(want[i]))),
          'the table\'s total shows the pixel\'s value', totalText);
    const firstRow = await page.locator('#dbg-path-table tr[data-bounce="1"] + tr.sub').textContent();
    check(/pdf/.test(firstRow) && /(lit|blocked)/.test(firstRow), 'a step lists its light samples with pdf and verdict', firstRow);
    const matches = await page.locator('#dbg-path-table .match').count();
    const mismatches = await page.locator('#dbg-path-table .mismatch').count();
    check(matches >= 1 && mismatches === 0, 'each step\'s direct light equals its light samples\' f·L·cos θ/pdf averaged',
          `${matches} match, ${mismatches} differ`);
    const cam = await page.evaluate(() => window.viewer.scene.camera.position);
    const seg0 = r.segments[0];
    check(seg0.kind === 'camera' && seg0.from.every((x, i) => Math.abs(x - cam[i]) <= 1e-5 * Math.max(1, Math.abs(cam[i]))),
          'the 3D path starts at the camera', `${JSON.stringify(seg0)} vs ${cam}`);
    check(seg0.to.every((x, i) => x === r.steps[0].point[i]), 'the camera segment ends at the first hit');
    const drawn = await page.evaluate(() => window.viewer.debug.overlay.group.children.length);
    check(drawn >= 3, 'the path is drawn in the 3D view', String(drawn));
    await shoot('debug_mode.jpg');

    // A hit of the path into the intersection tester: the same ray against
    // the same primitive hits it at the same t.
    const step2 = r.steps[1];
    const picked = await debugCall(page, 'intersect', () =>
      page.locator('#dbg-path-table tr[data-bounce="2"] + tr.sub button', {hasText: 'test the hit'}).click());
    check(picked.ok && picked.result.hit && picked.result.primitive === step2.primitive &&
          picked.result.t === step2.t && sameArrays(picked.result.normal, step2.normal),
          'a path step picked into the intersection tester: the same primitive hit at the same t and normal',
          JSON.stringify(picked.result || picked.error));

    // Intersection tester: typed-in rays against known shapes.
    await page.click('#debug-tabs button[data-tool=intersect]');
    const typeRay = async (o, d, minT, maxT) => {
      await page.fill('#dbg-origin', o);
      await page.fill('#dbg-direction', d);
      await page.fill('#dbg-min-t', minT);
      await page.fill('#dbg-max-t', maxT);
    };
    await page.selectOption('#dbg-shape', 'triangle');
    await page.fill('#dbg-p1', '-1, -1, -2');
    await page.fill('#dbg-p2', '1, -1, -2');
    await page.fill('#dbg-p3', '0, 1, -2');
    await typeRay('0, 0, 0', '0, 0, -1', '0', 'inf');
    let t = await debugCall(page, 'intersect', () => page.click('#dbg-intersect-run'));
    const kvTable = () => page.$$eval('#dbg-intersect-table tr',
                                      (trs) => Object.fromEntries(trs.map((r) => [r.cells[0].textContent, r.cells[1].textContent])));
    let table = await kvTable();
    check(t.ok && t.result.hit && t.result.t === 2 && sameArrays(t.result.normal, [0, 0, 1]),
          'a ray hits the triangle at t = 2 with normal (0, 0, 1)', JSON.stringify(t.result));
    check(table.result === 'hit' && table.t === '2' && table.normal === '(0, 0, 1)', 'the panel shows hit, t and the normal',
          JSON.stringify(table));
    await typeRay('0.2, 0.1, 0', '0, 0, -2', '0', 'inf');
    t = await debugCall(page, 'intersect', () => page.click('#dbg-intersect-run'));
    check(t.ok && t.result.hit && t.result.t === 1 && sameArrays(t.result.point.map(Math.fround), [0.2, 0.1, -2].map(Math.fround)),
          'direction not normalised: t in units of its length (t = 1 at (0.2, 0.1, -2))', JSON.stringify(t.result));
    await typeRay('0, 0, 0', '0, 0, -1', '0', '1.5');
    t = await debugCall(page, 'intersect', () => page.click('#dbg-intersect-run'));
    table = await kvTable();
    check(t.ok && !t.result.hit && table.result === 'miss' && table.t === undefined, 'beyond max_t: a miss', JSON.stringify(table));
    await page.selectOption('#dbg-shape', 'sphere');
    await page.fill('#dbg-center', '0, 0, -3');
    await page.fill('#dbg-radius', '0.5');
    await typeRay('0, 0, 0', '0, 0, -1', '0', 'inf');
    t = await debugCall(page, 'intersect', () => page.click('#dbg-intersect-run'));
    check(t.ok && t.result.hit && t.result.t === 2.5 && sameArrays(t.result.normal, [0, 0, 1]),
          'a ray hits the sphere at t = 2.5 with normal (0, 0, 1)', JSON.stringify(t.result));
    await typeRay('0, 0, -3', '1, 0, 0', '0', 'inf');
    t = await debugCall(page, 'intersect', () => page.click('#dbg-intersect-run'));
    check(t.ok && t.result.hit && t.result.t === 0.5 && sameArrays(t.result.normal, [1, 0, 0]),
          'from inside the sphere: the far side at t = 0.5, normal (1, 0, 0)', JSON.stringify(t.result));
    await shoot('debug_intersect.png');

    // Light-sample tester: every sample point lies on the area light.
    await page.click('#debug-tabs button[data-tool=lights]');
    await page.selectOption('#dbg-light', '0');
    await page.fill('#dbg-lsamples', '200');
    const l = await debugCall(page, 'lights', () => page.click('#dbg-lights-run'));
    check(l.ok && l.result.samples.length === 200 && l.result.light_shape.type === 'area',
          'the light-sample tester answers with 200 samples of the area light', l.error);
    const pts = await page.evaluate(() => window.viewer.debugState.samplePoints);
    const sh = l.result.light_shape;
    const dot = (a, c) => a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
    const sub = (a, c) => [a[0] - c[0], a[1] - c[1], a[2] - c[2]];
    const nrm = [sh.dim_x[1] * sh.dim_y[2] - sh.dim_x[2] * sh.dim_y[1], sh.dim_x[2] * sh.dim_y[0] - sh.dim_x[0] * sh.dim_y[2],
                 sh.dim_x[0] * sh.dim_y[1] - sh.dim_x[1] * sh.dim_y[0]];
    const nlen = Math.hypot(...nrm), ext = Math.hypot(...sh.dim_x) + Math.hypot(...sh.dim_y);
    const off = pts.map((p) => {
      const d = sub(p, sh.position);
      return {plane: Math.abs(dot(d, nrm)) / nlen, u: dot(d, sh.dim_x) / dot(sh.dim_x, sh.dim_x),
              v: dot(d, sh.dim_y) / dot(sh.dim_y, sh.dim_y)};
    });
    check(pts.length === 200 && off.every((o) => o.plane <= 1e-4 * ext && Math.abs(o.u) <= 0.5 + 1e-4 && Math.abs(o.v) <= 0.5 + 1e-4),
          'the drawn sample points lie on the light\'s rectangle', JSON.stringify(off.slice(0, 3)));
    const us = off.map((o) => o.u);
    check(Math.min(...us) < -0.3 && Math.max(...us) > 0.3, 'the samples spread over the light');
    await shoot('debug_lights.png');

    // Absurd input: a 4xx, the reason in the page, and the server goes on.
    const refused = async (what, tool, setup, pattern) => {
      await setup();
      const e = await debugCall(page, tool, () => page.click(`#dbg-${tool}-run`));
      const shownText = await page.locator(`#dbg-${tool}-out`).textContent();
      const bannerText = await page.locator('#banner').textContent();
      check(!e.ok && e.status >= 400 && e.status < 500 && pattern.test(e.error) && shownText.includes(e.error) &&
            bannerText.includes(e.error), `${what}: refused with a 4xx and the reason in the page`, `${e.status} ${e.error}`);
    };
    await page.click('#debug-tabs button[data-tool=intersect]');
    await refused('a zero direction', 'intersect', () => typeRay('0, 0, 0', '0, 0, 0', '0', 'inf'), /direction/);
    await refused('a NaN direction', 'intersect', () => typeRay('0, 0, 0', '0, nan, -1', '0', 'inf'), /direction/);
    await refused('min_t > max_t', 'intersect', () => typeRay('0, 0, 0', '0, 0, -1', '3', '1'), /min_t/);
    await refused('a negative radius', 'intersect', async () => {
      await typeRay('0, 0, 0', '0, 0, -1', '0', 'inf');
      await page.fill('#dbg-radius', '-1');
    }, /radius/);
    await page.click('#debug-tabs button[data-tool=path]');
    await refused('a pixel outside the image', 'path', () => page.fill('#dbg-x', '120'), /outside/);
    await refused('a sample index beyond -s', 'path', async () => {
      await page.fill('#dbg-x', '3');
      await page.fill('#dbg-sample', '1');
    }, /sample index 1/);
    await page.click('#debug-tabs button[data-tool=lights]');
    await refused('a light out of range', 'lights', () => page.evaluate(() => {
      document.getElementById('dbg-light').add(new Option('9', '9'));
      document.getElementById('dbg-light').value = '9';
    }), /light 9/);
    await page.click('#debug-tabs button[data-tool=path]');
    await page.fill('#dbg-sample', '0');
    const again = await debugCall(page, 'path', () => page.click('#dbg-path-run'));
    check(again.ok && v.proc.exitCode === null, 'the server keeps serving after the refusals', again.error);
    // The browser logs each refused request (HTTP 400) on the console; anything else is a fault.
    const refusedLog = (e) => /^Failed to load resource: the server responded with a status of 400/.test(e);
    const refusals = errors.filter(refusedLog).length;
    check(refusals === 7, 'the seven refusals were HTTP 400', String(refusals));
    check(errors.filter((e) => !refusedLog(e)).length === 0, 'no script errors in the page', errors.join('; '));
  });
};

// A crash in the build's code during a Debug mode call is a message naming
// the function; the next call works.
cases.debug_crash = async () => {
  await withViewerPage(['-r', '64', '48', '-s', '1', '-t', '2', '--seed', '13', SCENE()], async (page, v) => {
    await renderEnd(page, await lastJob(page));
    await openDebug(page);
    await page.click('#debug-tabs button[data-tool=intersect]');
    const e = await debugCall(page, 'intersect', () => page.click('#dbg-intersect-run'));
    const text = await page.locator('#banner').textContent();
    check(!e.ok && e.status === 500 && text.includes('planted_crash_in_debug_tool crashed: SIGSEGV while debugging'),
          'the crash is reported with the function and the signal', `${e.status}: ${text}`);
    await page.screenshot({path: path.join(OUT, 'debug_crash.png')});
    await page.fill('input[name=seed]', '0');
    await page.dispatchEvent('input[name=seed]', 'change');
    await page.waitForFunction(() => window.viewer.settings.seed === 0);
    const ok = await debugCall(page, 'intersect', () => page.click('#dbg-intersect-run'));
    check(ok.ok && ok.result.hit && ok.result.t === 2, 'the next call works (the default ray hits its triangle at t = 2)',
          JSON.stringify(ok.result || ok.error));
    check(v.proc.exitCode === null, 'the server process is still running');
  }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'crash'}});
};

// Unfinished code in a Debug mode call (the test build prints a stub's
// TODO line in every worker): the banner names the part, the function and
// the file, and the tool still answers.
cases.debug_todo = async () => {
  await withViewerPage(['-r', '64', '48', '-s', '1', '-t', '2', SCENE()], async (page) => {
    await renderEnd(page, await lastJob(page));
    await openDebug(page);
    await page.click('#debug-tabs button[data-tool=intersect]');
    const e = await debugCall(page, 'intersect', () => page.click('#dbg-intersect-run'));
    const text = await page.locator('#banner').textContent();
    check(e.ok && e.result.hit && e.result.t === 2, 'the tool answers', JSON.stringify(e.result || e.error));
    check(await page.locator('#banner').isVisible() &&
          text.includes('Part 1 not implemented (TODO: raytrace_pixel, stages/part1_raytracing/pixel_sampling.cpp)'),
          'the banner names the part, the function and the file', text);
    await page.screenshot({path: path.join(OUT, 'debug_todo.png')});
  }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'todo'}});
};

// Not a test: timings for the report.
async function measure() {
  const results = {};
  if (args.measure !== 'bvh') {
    const flags = ['-r', '480', '360', '-t', '2', '-s', '64', '-l', '4', '-m', '5', SCENE()];
    await withViewerPage(flags, async (page, v) => {
      const t0 = Date.now();
      await page.goto(v.url);
      await page.waitForFunction(() => document.body.dataset.ready === '1');
      const job = await lastJob(page);
      await waitEvent(page, `e.type === 'frame' && e.job === ${job}`, 600000);
      results.first_frame_ms_from_page_load = Date.now() - t0;
      const end = await renderEnd(page, job, 600000);
      const st = await page.evaluate(() => window.viewer.status);
      results.frames = await page.evaluate((j) => window.viewer.events.filter((e) => e.type === 'frame' && e.job === j)
        .map((e) => ({samples: e.samples, elapsed_s: e.elapsed, pass_s: e.seconds})), job);
      results.passes = st.frame.pass + 1;
      results.render_wall_s = st.wall;
      results.passes_per_second = (st.frame.pass + 1) / st.wall;
      results.end = end.state;
    }, {load: false});
  }
  const flags = ['-r', '480', '360', '-t', '2', path.join(args.scenes, args.scene || 'CBdragon_large.dae')];
  await withViewerPage(flags, async (page) => {
    await page.keyboard.press('v');
    await page.waitForFunction(() => document.body.dataset.bvhNode === '0', null, {timeout: 600000});
    // What a frame looks like while the camera moves.
    await page.evaluate(() => { window.viewer.view3d.moving(true); window.viewer.view3d.redraw(); });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    await page.screenshot({path: path.join(OUT, 'bvh_dragon_large_moving.png')});
    await page.evaluate(() => window.viewer.view3d.moving(false));
    await page.screenshot({path: path.join(OUT, 'bvh_dragon_large_still.png')});
    const m = await page.evaluate((n) => window.viewer.view3d.measure(n), Number(args.frames || 120));
    const stats = (xs) => {
      xs.sort((a, c) => a - c);
      return {late: xs.filter((x) => x > 20).length / xs.length, median: xs[Math.floor(xs.length / 2)], p95: xs[Math.floor(xs.length * 0.95)], max: xs[xs.length - 1]};
    };
    // Frame: between two animation frames; draw: render() until the GPU
    // process has finished it (gl.finish).
    results.bvh_frame_ms = stats(m.frames);
    results.bvh_draw_ms = stats(m.draws);
    results.bvh_triangles_drawn_while_moving = m.triangles;
    await page.screenshot({path: path.join(OUT, 'bvh_dragon_large.png')});
  });
  console.log(JSON.stringify(results, null, 2));
}

const main = async () => {
  if (args.measure) return measure();
  const c = cases[args.case];
  if (!c) {
    console.log(`FAIL - unknown case '${args.case}' (cases: ${Object.keys(cases).join(', ')})`);
    process.exit(1);
  }
  await c();
};
main().then(() => {
  console.log(`${passes} passed, ${failures} failed`);
  process.exit(failures ? 1 : 0);
}, (e) => {
  console.log(`FAIL - ${args.case}: ${e.stack || e}`);
  console.log(`${passes} passed, ${failures + 1} failed`);
  process.exit(1);
});
