// Render mode in the browser: the progressive render against the command
// line, restarts, cell renders, overlays (tests per ray, sample rate,
// normals, the difference with a case), the camera file round trip, the
// TODO banner and a crash reported, and the README's screenshots.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import {args, OUT, check, runCli, withViewerPage, waitEvent, lastJob, renderEnd, canvasPixels, pngPixels, fetchBytes, sameArrays, SCENE, FLAGS} from './harness.mjs';

export const cases = {};


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

    const cliPng = path.join(OUT, 'cli_render.png'), cliPfm = path.join(OUT, 'cli_render.pfm');
    runCli([...FLAGS, '-f', cliPng, '--pfm', cliPfm, SCENE()]);
    const served = await fetchBytes(v, `/api/png?job=${job}`);
    check(Buffer.compare(served, fs.readFileSync(cliPng)) === 0,
          'Save PNG gives the bytes of the command line\'s PNG at the same settings and seed');
    const shown = await canvasPixels(page), cli = await pngPixels(page, cliPng);
    check(cli.w === 96 && cli.h === 72 && sameArrays(shown, cli.data),
          'the page shows the command line\'s pixels after tone mapping');
    const pfm = await fetchBytes(v, `/api/pfm?job=${job}`);
    check(Buffer.compare(pfm, fs.readFileSync(cliPfm)) === 0, 'Save PFM gives the bytes of the command line\'s --pfm');

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
    check(diff.hints.length === 0 && !diff.note && await page.locator('#diff-hints').isHidden(),
          'a render that matches gets no likely causes', JSON.stringify(diff));
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

// A build whose part prints a stub's TODO line: the page says which part
// and function, and still shows the image.
cases.todo_banner = async () => {
  await withViewerPage(['-r', '64', '48', '-s', '2', '-t', '2', SCENE()], async (page) => {
    const end = await renderEnd(page, await lastJob(page));
    const text = await page.locator('#banner').textContent();
    check(await page.locator('#banner').isVisible() &&
          text.includes('Part 1, raytrace_pixel (stages/part1_raytracing/pixel_sampling.cpp): not written yet; meanwhile one sample through the pixel centre, whatever -s'),
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
    check(/^planted_crash_in_render crashed: SIGSEGV while rendering \(viewer\/worker\.cpp:\d+\)$/.test(text),
          'the banner names the function, the signal, and the file and line (the test build has debug information)', text);
    await page.screenshot({path: path.join(OUT, 'crash_banner.png')});
    // Every render thread crashing at once (-t 4, a null write in every
    // pixel), and a stack overflow (endless recursion): one report each.
    await page.fill('input[name=threads]', '4');
    for (const [seed, fn] of [[16, 'planted_crash_in_render'], [17, 'planted_endless_recursion']]) {
      const last = await lastJob(page);
      await page.fill('input[name=seed]', String(seed));
      await page.dispatchEvent('input[name=seed]', 'change');
      const again = await waitEvent(page, `e.type === 'render' && e.job > ${last}`);
      const crashed = await renderEnd(page, again.job);
      const shown = await page.locator('#banner').textContent();
      check(crashed.state === 'crashed' && new RegExp(`^${fn} crashed: SIGSEGV while rendering \\(viewer/worker\\.cpp:\\d+\\)$`).test(shown),
            `--seed ${seed}: one report naming ${fn}, its file and line`, `${crashed.state}: ${JSON.stringify(shown)}`);
    }
    await page.screenshot({path: path.join(OUT, 'crash_threads_banner.png')});
    await page.fill('input[name=threads]', '2');
    const beforeNext = await lastJob(page);
    await page.fill('input[name=seed]', '0');
    await page.dispatchEvent('input[name=seed]', 'change');
    const next = await waitEvent(page, `e.type === 'render' && e.job > ${beforeNext}`);
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
      const clip = {x: 0, y: 0, width: 1400, height: 860};
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

// The difference overlay while the case's render is still at an earlier
// pass (the test build holds each pass until the test lets it go on): the
// page says when the difference comes, with no error; then the last pass
// is compared and matches. Waits on the page's events only.
cases.diff_pending = async () => {
  const gate = fs.mkdtempSync(path.join(os.tmpdir(), 'pt-viewer-gate-'));
  const flags = ['-r', '64', '48', '-s', '2', '-t', '2', SCENE()];
  try {
    await withViewerPage(flags, async (page, v, errors) => {
      await page.selectOption('#case', 'p3_spheres_light');
      const before = await lastJob(page);
      await page.click('#btn-apply-case');
      const caseRender = await waitEvent(page, `e.type === 'render' && e.job > ${before} && e.settings.samples === 16`);
      const pending = await waitEvent(page, `e.type === 'diff_pending' && e.job === ${caseRender.job}`);
      check(pending.message === 'difference shown when the render reaches 16 samples (now 1)',
            'after the first pass of the case\'s render the page says when the difference comes', JSON.stringify(pending));
      const note = await page.locator('#overlay-note').textContent();
      check(note === `p3_spheres_light: ${pending.message}`, 'the overlay\'s note says it', note);
      await page.screenshot({path: path.join(OUT, 'diff_pending.png')});
      for (let k = 1; k <= 4; ++k) fs.writeFileSync(path.join(gate, `pass${k}`), '');
      const diff = await waitEvent(page, `e.type === 'diff' && e.job === ${caseRender.job}`);
      check(diff.summary && diff.summary.startsWith('matches the reference'), 'at 16 samples the render is compared: it matches',
            JSON.stringify(diff));
      check(diff.hints.length === 0 && !diff.note && await page.locator('#diff-hints').isHidden(),
            'a render that matches gets no likely causes', JSON.stringify(diff));
      const wrong = await page.evaluate(() => window.viewer.events.filter((e) => e.type === 'diff' && e.error));
      check(wrong.length === 0, 'no difference request was answered with an error', JSON.stringify(wrong));
      check(errors.length === 0, 'no errors in the page (no failed request either)', errors.join('; '));
      await page.screenshot({path: path.join(OUT, 'diff_done.png')});
    }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'gate', PT_VIEWER_GATE: path.join(gate, 'pass')}});
  } finally {
    fs.rmSync(gate, {recursive: true, force: true});
  }
};

// The difference overlay of a render that differs from its case's
// reference (the test build sends every frame times pi, as a diffuse BSDF
// that leaves out the division by pi renders): the likely causes are in
// words under the verdict, the nearest the known bug in diffuse_f; each line
// is inside the view, wraps, and leaves the image and the verdict alone.
cases.diff_hints = async () => {
  const flags = ['-r', '64', '48', '-s', '2', '-t', '2', SCENE()];
  await withViewerPage(flags, async (page, v, errors) => {
    await page.selectOption('#case', 'p3_spheres_light');
    const before = await lastJob(page);
    await page.click('#btn-apply-case');
    const caseRender = await waitEvent(page, `e.type === 'render' && e.job > ${before} && e.settings.samples === 16`);
    // The last pass is compared before the render's end is logged: from
    // then on the page shows that comparison.
    const end = await renderEnd(page, caseRender.job);
    check(end.state === 'done' && end.samples === 16, 'the case\'s render reaches 16 samples', JSON.stringify(end));
    const diff = await page.evaluate((j) => window.viewer.events.filter((e) => e.type === 'diff' && e.job === j).pop() || {},
                                     caseRender.job);
    check(diff.summary && diff.summary.startsWith('differs from the reference'),
          'the render times pi differs from case p3_spheres_light', JSON.stringify(diff));
    check(Array.isArray(diff.hints) && diff.hints.length >= 1 && diff.hints.length <= 3 &&
          diff.hints[0].function === 'diffuse_f' && diff.hints[0].file === 'common/bsdf.h',
          'the nearest likely cause is the known bug in diffuse_f (common/bsdf.h), at most three in all', JSON.stringify(diff.hints));
    const shown = await page.locator('#diff-hints p').allTextContents();
    check(shown.length === diff.hints.length && shown[0].startsWith(`Likely cause 1 of ${diff.hints.length}: ` +
          'every lit image is too bright by about pi (image x3.1): is the diffuse BSDF the albedo divided by pi?') &&
          shown[0].endsWith('Look at diffuse_f in common/bsdf.h, and read "Given code" in stages/part3_direct_lighting/README.md.'),
          'the page says each likely cause in words, with the function, file and README section to read', JSON.stringify(shown));
    check(!shown.some((t) => t.includes('`')) && await page.locator('#diff-hints code, #diff-hints pre').count() === 0,
          'in plain words: no code marks or code blocks', JSON.stringify(shown));
    // Laid out: below the verdict, inside the window, wrapped (nothing
    // wider than its box), not over the image or the verdict.
    const layout = await page.evaluate(() => {
      const r = (id) => document.getElementById(id).getBoundingClientRect();
      const box = document.getElementById('diff-hints');
      return {hints: r('diff-hints').toJSON(), note: r('overlay-note').toJSON(), canvas: r('render-canvas').toJSON(),
              width: window.innerWidth, overflow: box.scrollWidth - box.clientWidth,
              lines: [...box.querySelectorAll('p')].map((p) => p.getBoundingClientRect().height)};
    });
    const below = (a, b) => a.top >= b.bottom - 0.5;
    check(below(layout.hints, layout.note) && below(layout.note, layout.canvas) && layout.hints.right <= layout.width &&
          layout.overflow <= 0 && layout.lines.every((h) => h > 0),
          'the causes sit under the verdict, inside the window, wrapped, over nothing else', JSON.stringify(layout));
    await page.locator('#diff-hints').scrollIntoViewIfNeeded();
    await page.screenshot({path: path.join(OUT, 'diff_hints.png')});

    // They belong to the difference: with the overlay off they go.
    await page.selectOption('#overlay', '');
    check(await page.locator('#diff-hints').isHidden(), 'with the overlay off, no likely causes are shown');
    check(errors.length === 0, 'no errors in the page', errors.join('; '));
  }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'pi'}});
};

// A build whose parts 2 to 5 are still stubs (the test build pretends so):
// with no --part, the page starts at part 1, the last part written, and
// says why in one line.
cases.start_part = async () => {
  await withViewerPage(['-r', '64', '48', '-s', '2', '-t', '2', SCENE()], async (page) => {
    const job = await waitEvent(page, `e.type === 'render'`);
    check(job.settings.part === 1, 'the first render is at part 1', String(job.settings.part));
    check((await page.inputValue('select[name=part]')) === '1', 'the settings show part 1');
    const note = await page.locator('#start-note').textContent();
    check(await page.locator('#start-note').isVisible() &&
          note === 'Starting at part 1, the last part written: parts 2, 3, 4, 5 still have TODO stubs. Pick a part under "part" to see another.',
          'one line says why and which part to pick', note);
    await renderEnd(page, job.job);
    await page.screenshot({path: path.join(OUT, 'start_part.png')});
  }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'stubs'}});
  // With --part, the command line decides.
  await withViewerPage(['--part', '3', '-r', '64', '48', '-s', '2', '-t', '2', SCENE()], async (page) => {
    const job = await waitEvent(page, `e.type === 'render'`);
    check(job.settings.part === 3 && !(await page.locator('#start-note').isVisible()), '--part 3 starts at part 3, no note',
          String(job.settings.part));
  }, {bin: args.planted, env: {PT_VIEWER_PLANT: 'stubs'}});
};
