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
import {args, OUT, summary, withViewerPage, waitEvent, lastJob, renderEnd, SCENE, startViewer, stopViewer, postJson, jobEnd,
        rawRequest, memoryMB, resetPeakMemory} from './harness.mjs';
import {cases as render} from './cases_render.mjs';
import {cases as bvh} from './cases_bvh.mjs';
import {cases as debug} from './cases_debug.mjs';
import {cases as server} from './cases_server.mjs';
import {cases as access} from './cases_access.mjs';
import {cases as stuck} from './cases_stuck.mjs';
import path from 'node:path';

const cases = Object.assign({}, render, bvh, debug, server, access, stuck);

// Not a test: the server's memory (resident, in MB) with three 8192x4096
// part 1 renders in a row, and its peak while six clients download the
// last one's PFM (and then its PNG) at once.
async function measureMemory() {
  const v = await startViewer(args.viewer, ['--part', '1', '-r', '8192', '4096', '-s', '1', '-t', '2', SCENE()]);
  const results = {viewer: args.viewer, start: memoryMB(v.proc.pid).rss, after_render: []};
  try {
    let job = null;
    for (let i = 0; i < 3; ++i) {
      job = (await postJson(v, '/api/render', {seed: i})).json.job;
      const end = await jobEnd(v, job);
      if (end.state !== 'done') throw new Error(`render ${job}: ${end.state} ${end.message}`);
      results.after_render.push(memoryMB(v.proc.pid).rss);
    }
    for (const kind of ['pfm', 'png']) {
      resetPeakMemory(v.proc.pid);
      const before = memoryMB(v.proc.pid).rss;
      const got = await Promise.all([...Array(6).keys()].map(() =>
        rawRequest(v, {path: `/api/${kind}?job=${job}&token=${v.token}`, discard: true})));
      results[`six_${kind}_downloads`] = {before, peak: memoryMB(v.proc.pid).peak, after: memoryMB(v.proc.pid).rss,
                                          bytes_each: got.map((g) => g.bytes)};
    }
  } finally {
    await stopViewer(v);
  }
  console.log(JSON.stringify(results, null, 2));
}

// Not a test: timings for the report.
async function measure() {
  if (args.measure === 'memory') return measureMemory();
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
  const {passes, failures} = summary();
  console.log(`${passes} passed, ${failures} failed`);
  process.exit(failures ? 1 : 0);
}, (e) => {
  console.log(`FAIL - ${args.case}: ${e.stack || e}`);
  const {passes, failures} = summary();
  console.log(`${passes} passed, ${failures + 1} failed`);
  process.exit(1);
});
