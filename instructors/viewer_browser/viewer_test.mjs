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
        runCli,
        rawRequest, memoryMB, resetPeakMemory} from './harness.mjs';
import {cases as render} from './cases_render.mjs';
import {cases as bvh} from './cases_bvh.mjs';
import {cases as debug} from './cases_debug.mjs';
import {cases as server} from './cases_server.mjs';
import {cases as access} from './cases_access.mjs';
import {cases as stuck} from './cases_stuck.mjs';
import {cases as sampling} from './cases_sampling.mjs';
import fs from 'node:fs';
import path from 'node:path';

const cases = Object.assign({}, render, bvh, debug, server, access, stuck, sampling);

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

// Not a test: the progressive render's whole time in the viewer (from the
// request to the last pass) against the command line's render at the same
// settings, in turns, --runs N times each (default 3); --compare BIN times
// another viewer build too. The settings: --flags "..." (default CBbunny
// 480x360 -s 64 -l 4 -m 5 -t 2).
async function measureProgressive() {
  const flags = args.flags ? String(args.flags).split(/\s+/)
                           : ['-r', '480', '360', '-s', '64', '-l', '4', '-m', '5', '-t', '2', path.join(args.scenes, 'CBbunny.dae')];
  const runs = Number(args.runs || 3);
  const viewers = [['viewer', args.viewer]].concat(args.compare ? [['compare', args.compare]] : []);
  const results = {flags: flags.join(' '), runs: []};
  const seconds = (t0) => Number(process.hrtime.bigint() - t0) / 1e9;
  // CPU seconds of a process and its reaped children (/proc/PID/stat:
  // utime, stime, cutime, cstime, in ticks of 1/100 s), which the load of
  // other programs on the machine changes far less than wall time.
  const cpu = (pid) => {
    const f = fs.readFileSync(`/proc/${pid}/stat`, 'utf8');
    const v = f.slice(f.lastIndexOf(')') + 2).split(' ').map(Number);
    return (v[11] + v[12] + v[13] + v[14]) / 100;
  };
  for (let i = 0; i < runs; ++i) {
    const run = {};
    for (const [name, bin] of viewers) {
      const v = await startViewer(bin, flags);
      try {
        const t0 = process.hrtime.bigint(), c0 = cpu(v.proc.pid);
        const job = (await postJson(v, '/api/render', {})).json.job;
        const end = await jobEnd(v, job);
        run[`${name}_s`] = seconds(t0);
        run[`${name}_cpu_s`] = cpu(v.proc.pid) - c0;
        if (end.state !== 'done') throw new Error(`${name}: ${end.state} ${end.message}`);
        run[`${name}_passes`] = end.passes;
      } finally {
        await stopViewer(v);
      }
    }
    const t0 = process.hrtime.bigint(), c0 = cpu(process.pid);
    runCli([...flags.slice(0, -1), '--no-progress', '-f', path.join(OUT, 'bench.png'), flags[flags.length - 1]]);
    run.cli_s = seconds(t0);
    run.cli_cpu_s = cpu(process.pid) - c0;
    run.ratio = run.viewer_s / run.cli_s;
    run.cpu_ratio = run.viewer_cpu_s / run.cli_cpu_s;
    if (args.compare) {
      run.compare_ratio = run.compare_s / run.cli_s;
      run.compare_cpu_ratio = run.compare_cpu_s / run.cli_cpu_s;
    }
    results.runs.push(run);
    console.log(JSON.stringify(run));
  }
  const median = (xs) => xs.slice().sort((a, c) => a - c)[Math.floor(xs.length / 2)];
  for (const key of ['ratio', 'cpu_ratio'].concat(args.compare ? ['compare_ratio', 'compare_cpu_ratio'] : []))
    results[`median_${key}`] = median(results.runs.map((r) => r[key]));
  console.log(JSON.stringify(results, null, 2));
}

// Not a test: timings for the report.
async function measure() {
  if (args.measure === 'memory') return measureMemory();
  if (args.measure === 'progressive') return measureProgressive();
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
