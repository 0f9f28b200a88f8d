// BVH mode in the browser: the root and its children by the keys, the
// depth slider, and descending by clicking a child's box.
import path from 'node:path';
import {args, OUT, check, withViewerPage} from './harness.mjs';

export const cases = {};

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
    // The panel stands beside the scene's view, not over it.
    const boxes = await page.evaluate(() => {
      const r = (id) => {
        const b = document.getElementById(id).getBoundingClientRect();
        return [b.left, b.top, b.right, b.bottom];
      };
      return {canvas: r('three-canvas'), info: r('bvh-info')};
    });
    const [c, i] = [boxes.canvas, boxes.info];
    check(i[2] > i[0] && i[3] > i[1] && !(c[0] < i[2] && i[0] < c[2] && c[1] < i[3] && i[1] < c[3]),
          'the node\'s panel does not cover the scene (its box and the canvas\'s do not overlap)', JSON.stringify(boxes));
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
