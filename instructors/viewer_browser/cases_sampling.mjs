// Project 3-2 in the browser: a part 6 render of the mirror and glass
// spheres, Debug mode's BSDF sampler on the glass sphere (two directions,
// the Fresnel split) and on a microfacet sphere (the histogram against the
// pdf), and the environment map's sampling density at part 8.
import fs from 'node:fs';
import path from 'node:path';
import {args, OUT, check, withViewerPage, waitEvent, lastJob, renderEnd} from './harness.mjs';
import {debugCall} from './cases_debug.mjs';

export const cases = {};

const W = 400, H = 300;

// The option of a file select whose path ends with `name`.
async function pick(page, select, name) {
  const value = await page.evaluate(([s, n]) => [...document.querySelector(s).options].map((o) => o.value)
    .find((v) => v.endsWith(`/${n}`)), [select, name]);
  check(Boolean(value), `${name} is offered in ${select}`);
  await page.selectOption(select, value);
  return value;
}

// In render mode, `change` restarts the render (each settings change does,
// 120 ms after the last); the end of the render of the settings wanted.
async function renderWith(page, change, part, scene) {
  await page.click('#mode-render');
  await change();
  const started = await waitEvent(page, `e.type === 'render' && e.settings.part === ${part} && ` +
                                        `e.settings.scene.endsWith('/${scene}')`);
  return renderEnd(page, started.job, 180000);
}

async function openDebugTool(page, tool) {
  await page.click('#mode-debug');
  await page.waitForFunction(() => document.body.dataset.debugReady === '1', null, {timeout: 60000});
  await page.click(`#debug-tabs button[data-tool=${tool}]`);
}

// A click on the BSDF sampler's copy of the render at pixel (x, y) from the bottom.
async function clickPixel(page, x, y) {
  const box = await page.locator('#dbg-bpick').boundingBox();
  await page.mouse.click(box.x + (x + 0.5) * box.width / W, box.y + (H - y - 0.5) * box.height / H);
}

// PNG artefacts; --publish DIR: the README's pictures (JPEGs) of the two tools.
async function shoot(page, name, published) {
  const clip = {x: 0, y: 0, width: 1400, height: 900};
  await page.screenshot({path: path.join(OUT, name), clip});
  if (args.publish && published) {
    fs.mkdirSync(args.publish, {recursive: true});
    await page.screenshot({path: path.join(args.publish, published), type: 'jpeg', quality: 82, clip});
  }
}

cases.debug_sampling = async () => {
  const flags = ['--part', '6', '-r', String(W), String(H), '-s', '8', '-m', '4', '-t', '2', '--seed', '3',
                 path.join(args.scenes, 'CBspheres.dae')];
  await withViewerPage(flags, async (page, v, errors) => {
    // Part 6 renders: the selector offers parts 1 to 9 by name, the lens
    // and the map can be set.
    const end = await renderEnd(page, await lastJob(page), 180000);
    check(end.state === 'done', 'CBspheres renders at part 6', JSON.stringify(end));
    const parts = await page.$$eval('select[name=part] option', (os) => os.map((o) => o.textContent));
    check(parts.length === 9 && parts[5] === '6: mirror and glass' && parts[8] === '9: depth of field',
          'the part selector names parts 1 to 9', JSON.stringify(parts));
    check(await page.isEditable('input[name=lens_radius]') && await page.isEditable('input[name=focal_distance]') &&
          await page.isEnabled('select[name=env]'), 'the lens (-b, -d) and the map (-e) are editable');
    // The glass sphere is bright where the mirror's reflection and the refraction show the room.
    const mean = await page.evaluate(() => {
      const c = document.getElementById('render-canvas');
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let s = 0;
      for (let i = 0; i < d.length; i += 4) s += d[i] + d[i + 1] + d[i + 2];
      return s / (3 * c.width * c.height);
    });
    check(mean > 20, 'the part 6 render is not black', String(mean));
    await shoot(page, 'render_part6.png');

    // The BSDF sampler on the glass sphere: two directions and the split.
    await openDebugTool(page, 'bsdf');
    const glass = await debugCall(page, 'bsdf', () => clickPixel(page, 300, 50));
    check(glass.ok, 'the BSDF sampler answers on the glass sphere', glass.error);
    const g = glass.result;
    // A pixel of the copy is 0.6 CSS pixels: the click lands within one pixel.
    const fields = [Number(await page.inputValue('#dbg-bx')), Number(await page.inputValue('#dbg-by'))];
    check(g.pixel[0] === fields[0] && g.pixel[1] === fields[1] && Math.abs(g.pixel[0] - 300) <= 1 &&
          Math.abs(g.pixel[1] - 50) <= 1 && g.model === 'glass' && g.delta,
          'the clicked pixel (near (300, 50)) is the glass sphere, a delta BSDF', `${g.pixel} ${fields} ${g.model}`);
    check(g.samples.length === 4096 && g.directions.length === 2 && g.agrees,
          'glass: two directions from 4096 samples, chosen as often as reported', g.verdict);
    const rows = await page.locator('#dbg-bsdf-directions tr[data-scatter]').count();
    const fresnel = await page.locator('#dbg-bsdf-fresnel').textContent();
    check(rows === 2 && /reflected/.test(fresnel) && /refracted/.test(fresnel) && /R = /.test(fresnel),
          'the panel lists both directions and the Fresnel split', fresnel);
    check(await page.locator('#dbg-bsdf-lobe').isVisible(), 'the directions are drawn edge-on');
    const drawn = await page.evaluate(() => window.viewer.debug.overlay.group.children.length);
    check(drawn >= 4, 'the directions are drawn in the 3D view', String(drawn));
    await page.locator('#dbg-bsdf-directions').scrollIntoViewIfNeeded();
    await shoot(page, 'debug_bsdf_glass.png');

    // A microfacet sphere at part 7: the histogram against the pdf.
    const end7 = await renderWith(page, async () => {
      await pick(page, '#f-scene', 'CBspheres_microfacet.dae');
      await page.selectOption('select[name=part]', '7');
    }, 7, 'CBspheres_microfacet.dae');
    check(end7.state === 'done', 'CBspheres_microfacet renders at part 7', JSON.stringify(end7));
    await openDebugTool(page, 'bsdf');
    const metal = await debugCall(page, 'bsdf', () => clickPixel(page, 300, 50));
    check(metal.ok, 'the BSDF sampler answers on the gold sphere', metal.error);
    const m = metal.result;
    check(m.model === 'microfacet' && !m.delta && m.histogram.length === 30 && m.agrees,
          'the gold sphere: a histogram over 0-90 degrees that agrees with the pdf', m.verdict);
    const judged = m.histogram.filter((b) => b.judged).length;
    check(judged >= 10, 'the histogram judges the lobe in many bins', String(judged));
    const plotted = await page.evaluate(() => {
      const c = document.getElementById('dbg-bsdf-histogram');
      return c && c.width === 560 && c.getBoundingClientRect().width > 0;
    });
    check(plotted, 'the histogram is drawn in the panel');
    await page.locator('#dbg-bsdf-histogram').scrollIntoViewIfNeeded();
    await shoot(page, 'debug_bsdf_microfacet.png', 'debug_bsdf.jpg');

    // The environment map at part 8: its density as an image.
    await pick(page, '#f-env', 'sky_sun.exr');
    await page.selectOption('select[name=part]', '8');
    await page.waitForFunction(() => window.viewer.settings.part === 8 && /sky_sun/.test(window.viewer.settings.env));
    const env = await debugCall(page, 'envmap', () => page.click('#debug-tabs button[data-tool=envmap]'));
    check(env.ok && env.result.sampler === 'importance (part 8)' && env.result.max_ratio > 100,
          'the density of part 8\'s sampler: the sun far likelier than the average texel',
          JSON.stringify(env.error || env.result.max_ratio));
    await page.waitForFunction(() => {
      const img = document.getElementById('dbg-envmap-img');
      return img && img.complete && img.naturalWidth > 0;
    });
    const size = await page.evaluate(() => [document.getElementById('dbg-envmap-img').naturalWidth,
                                            document.getElementById('dbg-envmap-img').naturalHeight]);
    check(size[0] === env.result.width && size[1] === env.result.height, 'the density image is the map\'s size',
          JSON.stringify(size));
    await shoot(page, 'debug_envmap.png', 'debug_envmap.jpg');
    check(v.proc.exitCode === null, 'the server is still running');
    check(errors.length === 0, 'no script errors in the page', errors.join('; '));
  });
};
