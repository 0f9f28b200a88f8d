// Debug mode in the browser: the path inspector against the command
// line's PFM, the intersection and light-sample testers, refusals, and a
// crash and a TODO line in a Debug mode call.
import fs from 'node:fs';
import path from 'node:path';
import {args, OUT, check, runCli, withViewerPage, waitEvent, lastJob, renderEnd, sameArrays, SCENE} from './harness.mjs';

export const cases = {};

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

// A Debug mode call made by `run` (a click), to the page's event of its end.
export async function debugCall(page, tool, run) {
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
    check(!e.ok && e.status === 500 &&
          /planted_crash_in_debug_tool crashed: SIGSEGV while debugging \(viewer\/worker\.cpp:\d+\)$/.test(text),
          'the crash is reported with the function, the signal, and its file and line', `${e.status}: ${text}`);
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
          text.includes('Part 1, raytrace_pixel (stages/part1_raytracing/pixel_sampling.cpp): not written yet; meanwhile one sample through the pixel centre, whatever -s'),
          'the banner names the part, the function and the file', text);
    await page.screenshot({path: path.join(OUT, 'debug_todo.png')});
  }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'todo'}});
};

