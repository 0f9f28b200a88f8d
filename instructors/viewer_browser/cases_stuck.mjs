// Code that never finishes or crashes, in the browser (the test build's
// planted faults): a render and a Debug mode call that loop for ever say
// how long they have run and where they are stuck, and can be stopped; a
// Debug call whose page is closed is stopped by the viewer; a crash is one
// report naming the function, its file and line, however many threads
// crash at once.
import path from 'node:path';
import {args, OUT, check, withViewerPage, waitEvent, lastJob, renderEnd, workersOf, SCENE} from './harness.mjs';

export const cases = {};

const LOOP = /an infinite loop in planted_infinite_loop_in_(render|debug_tool) \(viewer\/worker\.cpp:\d+\)\?/;

cases.stuck_render = async () => {
  // --idle-stop 5: a live page asks again at once after each answer, well within it.
  const flags = ['--idle-stop', '5', '-r', '64', '48', '-s', '4', '-t', '2', '--seed', '15', SCENE()];
  let viewer = null;
  await withViewerPage(flags, async (page, v, errors) => {
    viewer = v;
    const job = await lastJob(page);
    // The worker reports no progress after 5 s; the page says so.
    const stall = await waitEvent(page, `e.type === 'stall' && e.job === ${job}`, 120000);
    check(stall.stalled.function === 'planted_infinite_loop_in_render' && /^viewer\/worker\.cpp:\d+$/.test(stall.stalled.where),
          'the stuck render is reported in the function that loops, with its file and line', JSON.stringify(stall.stalled));
    await page.waitForFunction(() => /no pixel finished for \d+ s/.test(document.getElementById('banner').textContent));
    const text = await page.locator('#banner').textContent();
    check(/no pixel finished for \d+ s: /.test(text) && LOOP.test(text), 'the banner says for how long no pixel finished and where',
          text);
    // The time since the render started counts on in the HUD.
    const t0 = Number(/running · ([\d.]+) s/.exec(await page.locator('#hud').textContent())[1]);
    await page.waitForFunction((t) => {
      const m = /running · ([\d.]+) s/.exec(document.getElementById('hud').textContent);
      return m && Number(m[1]) >= t + 1;
    }, t0);
    check(t0 >= 5, 'the HUD shows the time since the render started, counting on', `${t0} s, then more`);
    await page.screenshot({path: path.join(OUT, 'stuck_render.png')});
    await page.click('#btn-stop');
    const end = await renderEnd(page, job);
    check(end.state === 'cancelled' && workersOf(v, 'render').length === 0, 'Stop ends it: no render worker is left',
          `${end.state}, ${workersOf(v, 'render').length} left`);

    // A Debug mode call that loops: how long, where, and Stop.
    await page.keyboard.press('d');
    await page.waitForFunction(() => document.body.dataset.debugReady === '1', null, {timeout: 60000});
    await page.click('#debug-tabs button[data-tool=intersect]');
    await page.click('#dbg-intersect-run');
    await page.waitForFunction(() => /no answer for \d+ s/.test(document.getElementById('dbg-intersect-out').textContent),
                               null, {timeout: 120000});
    const running = await page.locator('#dbg-intersect-out').textContent();
    check(/^running… \d+ s — no answer for \d+ s: /.test(running) && LOOP.test(running),
          'the Debug call shows how long it runs and where it is stuck', running);
    await page.screenshot({path: path.join(OUT, 'stuck_debug.png')});
    const before = page.evaluate(() => window.viewer.events.filter((e) => e.type === 'debug').length);
    await page.click('#dbg-intersect-stop');
    await page.waitForFunction((n) => window.viewer.events.filter((e) => e.type === 'debug').length > n, await before);
    const stopped = await page.evaluate(() => window.viewer.events.filter((e) => e.type === 'debug').at(-1));
    check(!stopped.ok && stopped.status === 409 && stopped.error === 'stopped' && workersOf(v, 'debug').length === 0,
          'its Stop button ends it: "stopped", no Debug worker is left', JSON.stringify(stopped));
    check((await page.locator('#dbg-intersect-out').textContent()) === 'stopped', 'the panel says it was stopped');
    // Another one, then the page goes away.
    await page.click('#dbg-intersect-run');
    await page.waitForFunction(() => /running…/.test(document.getElementById('dbg-intersect-out').textContent));
    check(workersOf(v, 'debug').length === 1, 'a new Debug call runs', String(workersOf(v, 'debug').length));
    const ended = v.waitStderr(/viewer: stopped job (\d+) \(debug\): no page asked about it for 5 s/);
    await page.close();
    await ended;
    check(workersOf(v, 'debug').length === 0, 'once its page is closed, the viewer stops the Debug call (--idle-stop 5)');
    check(errors.filter((e) => !/status of 409/.test(e)).length === 0, 'no script errors in the page', errors.join('; '));
  }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'hang'}});
  check(viewer && viewer.proc.exitCode === 0, 'the viewer stops cleanly', String(viewer && viewer.proc.exitCode));
};
