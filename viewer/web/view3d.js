// The 3D modes: the camera (a rasterised preview to orbit, pan and zoom,
// "render from here", "save camera") and the BVH walk (the current node's
// box, its children's boxes, its primitives, a depth slider). three.js
// draws; the scene's triangles and the BVH come from the server, the BVH
// built by the build's own part 2 code in a worker.
import * as THREE from 'three';
import {parseBVH, box, area, raySpan} from '/web/bvh_data.js';
import {coarseMesh, indexedMesh} from '/web/mesh.js';

const $ = (id) => document.getElementById(id);

export function create(viewer, hooks) {
  const canvas = $('three-canvas');
  // Drawn on the CPU on machines without a GPU (SwiftShader): no
  // multisampling, and the lighting baked into vertex colours once, so that
  // a frame costs one pass over the triangles and no per-pixel lighting.
  const renderer = new THREE.WebGLRenderer({canvas, antialias: false, preserveDrawingBuffer: true});
  renderer.setPixelRatio(1);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x15161a);
  const camera = new THREE.PerspectiveCamera(30, 4 / 3, 0.01, 1000);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x444455, 1.6));
  const headlight = new THREE.DirectionalLight(0xffffff, 1.4);
  camera.add(headlight);
  scene.add(camera);

  const state = {
    mode: null, sceneKey: null, meshes: null, target: new THREE.Vector3(),
    bvh: null, bvhKey: null, node: 0, depthShown: -1, frameTimes: [], lastFrame: 0,
  };
  const groups = {camera: new THREE.Group(), bvh: new THREE.Group()};
  scene.add(groups.camera, groups.bvh);
  // Both sides: the Cornell boxes are seen from inside.
  const side = THREE.DoubleSide;
  const baseMaterial = new THREE.MeshBasicMaterial({vertexColors: true, side});
  const sphereMaterial = (rgb) => new THREE.MeshLambertMaterial({color: new THREE.Color(...rgb), side});
  // BVH mode: the vertex colours hold the shading only; the material gives the hue.
  const dimMaterial = new THREE.MeshBasicMaterial({vertexColors: true, color: 0x8a8a8a, side});
  const hiMaterial = new THREE.MeshBasicMaterial({vertexColors: true, color: 0xff9a2e, side});
  const dimSphere = new THREE.MeshLambertMaterial({color: 0x6a6a6a, side});
  const hiSphere = new THREE.MeshLambertMaterial({color: 0xff9a2e, side});

  // The drawing buffer's scale while the camera moves (0.4: a sixth of the pixels).
  const MOVING_PIXEL_RATIO = 0.4;

  const coarse = {camera: null, bvh: null};  // [full, coarse] of each mode's mesh

  // ------------------------------------------------------------ drawing

  let pending = false;
  function redraw() {
    if (pending) return;
    pending = true;
    requestAnimationFrame((t) => {
      pending = false;
      if (state.lastFrame) state.frameTimes.push(t - state.lastFrame);
      if (state.frameTimes.length > 600) state.frameTimes.shift();
      state.lastFrame = t;
      renderer.render(scene, camera);
    });
  }

  // The canvas fills the view; in BVH mode the node's panel stands beside
  // it (#bvh-info, 270 px), never over the scene.
  function fitCanvas() {
    const s = viewer.settings;
    const beside = state.mode === 'bvh' ? 290 : 0;
    const maxW = Math.max(320, Math.min(960, window.innerWidth - 320 - beside)), maxH = Math.max(240, window.innerHeight - 160);
    const k = Math.min(maxW / s.width, maxH / s.height);
    const w = Math.round(s.width * k), h = Math.round(s.height * k);
    renderer.setSize(w, h, true);
    camera.aspect = s.width / s.height;
    camera.updateProjectionMatrix();
  }

  // The render's camera: the server's, with -r, -c, -b, -d and the view
  // the page last rendered from.
  function placeCamera(cam) {
    camera.fov = cam.vfov;
    camera.near = Math.max(1e-4, cam.near);
    camera.far = cam.far;
    camera.position.fromArray(cam.position);
    camera.up.fromArray(cam.axis_y);
    state.target.fromArray(cam.target);
    camera.lookAt(state.target);
    camera.updateProjectionMatrix();
  }

  // ------------------------------------------------------------ geometry

  async function loadMesh() {
    const key = viewer.settings.scene;
    if (state.sceneKey === key && state.meshes) return;
    const res = await hooks.api('/api/mesh', viewer.request());
    const buf = await res.arrayBuffer();
    const head = new Uint32Array(buf, 0, 2);
    const nt = head[0], ns = head[1];
    const tris = new Float32Array(buf, 8, nt * 9);
    const nrms = new Float32Array(buf, 8 + nt * 36, nt * 9);
    const sph = new Float32Array(buf, 8 + nt * 72, ns * 4);
    const rgb = new Uint8Array(buf, 8 + nt * 72 + ns * 16, (nt + ns) * 3);
    groups.camera.clear();
    const geo = indexedMesh(tris, nrms, (t) => (rgb[3 * t] << 16) | (rgb[3 * t + 1] << 8) | rgb[3 * t + 2]);
    const colors = geo.getAttribute('color').array;
    // The shade times the triangle's colour (vertices are shared only
    // within one colour).
    for (let v = 0; v < geo.userData.owner.length; ++v) {
      const t = geo.userData.owner[v];
      for (let k = 0; k < 3; ++k) colors[3 * v + k] *= rgb[3 * t + k] / 255;
    }
    const full = new THREE.Mesh(geo, baseMaterial);
    groups.camera.add(full);
    const lod = coarseMesh(full);
    coarse.camera = lod ? [full, lod] : null;
    if (lod) groups.camera.add(lod);
    const sphereGeo = new THREE.SphereGeometry(1, 32, 16);
    for (let i = 0; i < ns; ++i) {
      const c = 3 * (nt + i);
      const m = new THREE.Mesh(sphereGeo, sphereMaterial([rgb[c] / 255, rgb[c + 1] / 255, rgb[c + 2] / 255]));
      m.position.set(sph[4 * i], sph[4 * i + 1], sph[4 * i + 2]);
      m.scale.setScalar(sph[4 * i + 3]);
      groups.camera.add(m);
    }
    state.meshes = {tris, nrms, rgb, sph, nt, ns, sphereGeo};
    state.sceneKey = key;
  }

  // ------------------------------------------------------------ camera controls

  // While the camera moves, frames are drawn at MOVING_PIXEL_RATIO of the
  // resolution, from the coarse copy; the full view comes back when it stops.
  function moving(on) {
    for (const pair of [coarse.camera, coarse.bvh]) {
      if (!pair) continue;
      pair[0].visible = !on;
      pair[1].visible = on;
    }
    const ratio = on ? MOVING_PIXEL_RATIO : 1;
    if (renderer.getPixelRatio() !== ratio) {
      renderer.setPixelRatio(ratio);
      fitCanvas();
    }
    if (!on) redraw();
  }
  let wheelTimer = null;

  let drag = null;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('mousedown', (e) => {
    drag = {x: e.clientX, y: e.clientY, x0: e.clientX, y0: e.clientY, pan: e.button === 2 || e.shiftKey};
    e.preventDefault();
  });
  window.addEventListener('mouseup', (e) => {
    if (!drag) return;
    const moved = Math.abs(e.clientX - drag.x0) + Math.abs(e.clientY - drag.y0);
    drag = null;
    moving(false);
    if (moved < 4 && state.mode === 'bvh') clickBox(e);
  });
  window.addEventListener('mousemove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    if (dx || dy) moving(true);
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.pan) pan(dx, dy); else orbit(dx, dy);
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    moving(true);
    zoom(Math.exp(e.deltaY * 0.001));
    clearTimeout(wheelTimer);
    wheelTimer = setTimeout(() => moving(false), 200);
  }, {passive: false});

  // Scratch vectors: a camera move allocates nothing.
  const tmp = {offset: new THREE.Vector3(), up: new THREE.Vector3(), right: new THREE.Vector3(),
               tilted: new THREE.Vector3(), upv: new THREE.Vector3()};
  function orbit(dx, dy) {
    const offset = tmp.offset.copy(camera.position).sub(state.target);
    const up = tmp.up.copy(camera.up).normalize();
    offset.applyAxisAngle(up, -dx * 0.005);
    const right = tmp.right.crossVectors(up, offset).normalize();
    const tilted = tmp.tilted.copy(offset).applyAxisAngle(right, dy * 0.005);
    // Stay off the poles, where the view would flip.
    if (Math.abs(tilted.dot(up)) < 0.98 * tilted.length()) offset.copy(tilted);
    camera.position.copy(state.target).add(offset);
    camera.lookAt(state.target);
    redraw();
  }
  function pan(dx, dy) {
    const dist = camera.position.distanceTo(state.target);
    const k = 2 * dist * Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) / canvas.clientHeight;
    const right = tmp.right.setFromMatrixColumn(camera.matrix, 0);
    const upv = tmp.upv.setFromMatrixColumn(camera.matrix, 1);
    const move = right.multiplyScalar(-dx * k).add(upv.multiplyScalar(dy * k));
    camera.position.add(move);
    state.target.add(move);
    camera.lookAt(state.target);
    redraw();
  }
  function zoom(f) {
    const offset = tmp.offset.copy(camera.position).sub(state.target).multiplyScalar(f);
    if (offset.length() < 1e-4) return;
    camera.position.copy(state.target).add(offset);
    redraw();
  }

  function view() {
    return {position: camera.position.toArray(), target: state.target.toArray(), up: camera.up.toArray()};
  }

  $('btn-render-here').addEventListener('click', async () => {
    viewer.camera = view();
    await hooks.setMode('render');
    await viewer.loadScene();
    hooks.startRender();
  });
  $('btn-save-camera').addEventListener('click', async () => {
    try {
      const res = await hooks.api('/api/camera-file', viewer.request({camera: view()}));
      const blob = await res.blob();
      const a = document.createElement('a');
      a.href = URL.createObjectURL(blob);
      a.download = 'camera.txt';
      document.body.appendChild(a);
      a.click();
      a.remove();
    } catch (e) {
      hooks.banner(e.message, 'error');
    }
  });
  $('btn-reset-camera').addEventListener('click', () => {
    viewer.camera = null;
    placeCamera(viewer.scene.default_camera);
    redraw();
  });

  // ------------------------------------------------------------ BVH

  async function loadBVH() {
    const req = viewer.request({cell: null});
    const key = JSON.stringify([req.scene, req.bvh_leaf, req.bvh_bins, req.part, req.width, req.height,
                                req.camera, req.camera_file]);
    if (state.bvhKey === key && state.bvh) return state.bvh;
    $('bvh-info').textContent = 'building the BVH…';
    let st = await hooks.api('/api/bvh', req);
    while (st.state === 'running') st = await viewer.waitStatus(st.job, 0);
    if (st.state !== 'done') {
      $('bvh-info').textContent = '';
      const lines = [st.message];
      if (st.todo.length) lines.push(hooks.todoText(st.todo));
      hooks.banner(lines.filter(Boolean).join('\n'), 'error');
      return null;
    }
    if (st.todo.length) hooks.banner(hooks.todoText(st.todo), 'todo');
    const res = await hooks.api(`/api/bvh-data?job=${st.job}`);
    const bvh = parseBVH(await res.arrayBuffer());
    buildLeafOrderMesh(bvh);
    state.bvh = bvh;
    state.bvhKey = key;
    state.node = 0;
    $('depth-slider').max = bvh.maxDepth;
    $('depth-slider').value = -1;
    state.depthShown = -1;
    return bvh;
  }

  // The triangles in the BVH's leaf order, so that a node's primitives
  // (a range of leaf entries) are one draw range.
  function buildLeafOrderMesh(bvh) {
    const {tris, sph, nt} = state.meshes;
    const triBefore = new Uint32Array(bvh.prims.length + 1);
    let count = 0;
    for (let k = 0; k < bvh.prims.length; ++k) {
      triBefore[k] = count;
      if (bvh.prims[k] < nt) ++count;
    }
    triBefore[bvh.prims.length] = count;
    const pos = new Float32Array(count * 9), nrm = new Float32Array(count * 9);
    let t = 0;
    for (let k = 0; k < bvh.prims.length; ++k) {
      const id = bvh.prims[k];
      if (id < nt) {
        pos.set(tris.subarray(9 * id, 9 * id + 9), 9 * t);
        nrm.set(state.meshes.nrms.subarray(9 * id, 9 * id + 9), 9 * t++);
      }
    }
    bvh.triBefore = triBefore;
    groups.bvh.clear();
    const geo = indexedMesh(pos, nrm, () => 0);
    // One mesh, each triangle drawn once: the node's range (orange) and the
    // rest (grey) are two groups of the same buffer.
    bvh.highlight = new THREE.Mesh(geo, [dimMaterial, hiMaterial]);
    bvh.triangles = count;
    groups.bvh.add(bvh.highlight);
    bvh.coarse = coarseMesh(bvh.highlight);
    coarse.bvh = bvh.coarse ? [bvh.highlight, bvh.coarse] : null;
    if (bvh.coarse) groups.bvh.add(bvh.coarse);
    bvh.spheres = [];
    for (let k = 0; k < bvh.prims.length; ++k) {
      const id = bvh.prims[k];
      if (id < nt) continue;
      const s = id - nt;
      const m = new THREE.Mesh(state.meshes.sphereGeo, dimSphere);
      m.position.set(sph[4 * s], sph[4 * s + 1], sph[4 * s + 2]);
      m.scale.setScalar(sph[4 * s + 3]);
      m.userData.entry = k;
      groups.bvh.add(m);
      bvh.spheres.push(m);
    }
    bvh.boxes = new THREE.Group();
    groups.bvh.add(bvh.boxes);
  }

  const EDGES = [[0, 1], [1, 3], [3, 2], [2, 0], [4, 5], [5, 7], [7, 6], [6, 4], [0, 4], [1, 5], [2, 6], [3, 7]];
  // Every box drawn is in one LineSegments (one draw call), coloured per
  // vertex; `list` holds [node, colour] pairs, drawn in order.
  const boxMaterial = new THREE.LineBasicMaterial({vertexColors: true, depthTest: false, transparent: true});
  function boxLines(bvh, list) {
    const pos = new Float32Array(list.length * 72), col = new Float32Array(list.length * 72);
    const f = bvh.f, rgb = new THREE.Color();
    let o = 0;
    for (const [i, color] of list) {
      rgb.setHex(color);
      for (const [a, c] of EDGES) {
        for (const corner of [a, c]) {
          pos[o] = f[8 * i + (corner & 1 ? 4 : 0)];
          pos[o + 1] = f[8 * i + (corner & 2 ? 5 : 1)];
          pos[o + 2] = f[8 * i + (corner & 4 ? 6 : 2)];
          col[o] = rgb.r;
          col[o + 1] = rgb.g;
          col[o + 2] = rgb.b;
          o += 3;
        }
      }
    }
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    geo.setAttribute('color', new THREE.BufferAttribute(col, 3));
    const lines = new THREE.LineSegments(geo, boxMaterial);
    // A few boxes: not worth testing against the view.
    lines.frustumCulled = false;
    return lines;
  }

  function children(bvh, i) {
    return bvh.u[8 * i + 7] === 0 ? [bvh.u[8 * i + 3], bvh.u[8 * i + 3] + 1] : [];
  }

  function showNode() {
    const bvh = state.bvh;
    if (!bvh || bvh.n === 0) return;
    const i = state.node;
    for (const c of bvh.boxes.children) c.geometry.dispose();
    bvh.boxes.clear();
    const list = [];
    if (state.depthShown >= 0) {
      for (let k = 0; k < bvh.n; ++k) if (bvh.depth[k] === state.depthShown) list.push([k, 0xe6d84a]);
    }
    list.push([i, 0xffffff]);
    const kids = children(bvh, i);
    if (kids.length) list.push([kids[0], 0xff4d4d], [kids[1], 0x4da6ff]);
    bvh.boxes.add(boxLines(bvh, list));
    const t0 = bvh.triBefore[bvh.lo[i]], t1 = bvh.triBefore[bvh.hi[i]];
    const setGroups = (g, a, b, n) => {
      g.clearGroups();
      if (a > 0) g.addGroup(0, a * 3, 0);
      if (b > a) g.addGroup(a * 3, (b - a) * 3, 1);
      if (n > b) g.addGroup(b * 3, (n - b) * 3, 0);
    };
    setGroups(bvh.highlight.geometry, t0, t1, bvh.triangles);
    if (bvh.coarse) {
      // The coarse mesh keeps the triangles' order: the node's range is
      // where its kept triangles fall.
      const kept = bvh.coarse.userData.kept;
      const first = (t) => {
        let l = 0, h = kept.length;
        while (l < h) {
          const m = (l + h) >> 1;
          if (kept[m] < t) l = m + 1; else h = m;
        }
        return l;
      };
      setGroups(bvh.coarse.geometry, first(t0), first(t1), kept.length);
    }
    for (const m of bvh.spheres) {
      const k = m.userData.entry;
      m.material = k >= bvh.lo[i] && k < bvh.hi[i] ? hiSphere : dimSphere;
    }
    const count = bvh.hi[i] - bvh.lo[i];
    const leaf = bvh.u[8 * i + 7] !== 0;
    const rays = bvh.entered[i], camRays = bvh.head.camera_rays;
    $('bvh-info').textContent =
      `node ${i}${leaf ? ' (leaf)' : ''}\n` +
      `depth ${bvh.depth[i]} of ${bvh.maxDepth}\n` +
      `primitives ${count.toLocaleString()}\n` +
      `surface area ${area(bvh, i).toPrecision(4)}\n` +
      `SAH cost ${bvh.sah[i].toFixed(2)}\n` +
      `camera rays in ${rays.toLocaleString()} of ${camRays.toLocaleString()}` +
      (kids.length ? `\nleft (red) ${(bvh.hi[kids[0]] - bvh.lo[kids[0]]).toLocaleString()}, ` +
                     `right (blue) ${(bvh.hi[kids[1]] - bvh.lo[kids[1]]).toLocaleString()}` : '');
    $('hud3d').textContent = `BVH: ${bvh.n.toLocaleString()} nodes, ${bvh.head.leaves.toLocaleString()} leaves, ` +
                             `depth ${bvh.head.depth}, SAH cost ${bvh.head.sah_cost.toFixed(2)}, ` +
                             `built in ${bvh.head.build_seconds.toFixed(3)} s by this build's part 2`;
    document.body.dataset.bvhNode = String(i);
    redraw();
  }

  function go(dir) {
    const bvh = state.bvh;
    if (!bvh || bvh.n === 0) return false;
    const kids = children(bvh, state.node);
    let next = -1;
    if (dir === 'parent') next = bvh.parent[state.node];
    else if (dir === 'left' && kids.length) next = kids[0];
    else if (dir === 'right' && kids.length) next = kids[1];
    if (next < 0) return false;
    state.node = next;
    showNode();
    return true;
  }

  function clickBox(e) {
    const bvh = state.bvh;
    if (!bvh) return;
    const r = canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, camera);
    // Each child's box the ray passes through, with where it enters and
    // leaves it. The nearer box wins, unless the ray's stretch in one box
    // lies within its stretch in the other (one box inside the other, as at
    // the root of a Cornell box, where the mesh's box sits inside the
    // walls'): then the inner box wins, or it could never be clicked.
    const hits = [];
    for (const [k, side] of children(bvh, state.node).map((c, j) => [c, j ? 'right' : 'left'])) {
      const span = raySpan(ray.ray, box(bvh, k));
      if (span) hits.push(Object.assign(span, {side}));
    }
    if (!hits.length) return;
    hits.sort((a, b) => a.enter - b.enter);
    const [near, far] = hits;
    const inner = far && far.leave <= near.leave ? far : near;
    go(inner.side);
  }

  $('btn-parent').addEventListener('click', () => go('parent'));
  $('btn-left').addEventListener('click', () => go('left'));
  $('btn-right').addEventListener('click', () => go('right'));
  $('depth-slider').addEventListener('input', () => {
    state.depthShown = Number($('depth-slider').value);
    $('depth-label').textContent = state.depthShown < 0 ? 'off' : String(state.depthShown);
    showNode();
  });

  // ------------------------------------------------------------ modes

  async function show(mode) {
    state.mode = mode;
    $('camera-tools').hidden = mode !== 'camera';
    $('bvh-tools').hidden = mode !== 'bvh';
    fitCanvas();
    try {
      if (!viewer.scene) await viewer.loadScene();
      await loadMesh();
      if (state.placedFor !== viewer.settings.scene) {
        placeCamera(viewer.scene.camera);
        state.placedFor = viewer.settings.scene;
      }
      groups.camera.visible = mode === 'camera';
      groups.bvh.visible = mode === 'bvh';
      if (mode === 'bvh') {
        const bvh = await loadBVH();
        if (bvh) showNode();
      } else {
        $('bvh-info').textContent = '';
        $('hud3d').textContent = `${state.meshes.nt.toLocaleString()} triangles, ${state.meshes.ns} spheres; ` +
                                 'drag to orbit, right-drag to pan, wheel to zoom';
      }
    } catch (e) {
      hooks.banner(e.message, 'error');
    }
    document.body.dataset.view3d = mode;
    redraw();
  }

  async function settingsChanged() {
    state.placedFor = null;
    state.bvhKey = null;
    if (state.mode) await show(state.mode);
  }

  // Frame times while the camera moves (drawn as while dragging): orbits by a small step per frame
  // for `frames` frames and returns the intervals between them (ms).
  function measure(frames) {
    moving(true);
    return new Promise((resolve) => {
      const times = [], draws = [];
      times.draws = draws;
      let last = 0, k = 0;
      const step = (t) => {
        if (last) times.push(t - last);
        last = t;
        if (k++ >= frames) {
          const drawn = renderer.info.render.triangles;
          moving(false);
          resolve({frames: times, draws, triangles: drawn});
          return;
        }
        const offset = tmp.offset.copy(camera.position).sub(state.target).applyAxisAngle(camera.up, 0.01);
        camera.position.copy(state.target).add(offset);
        camera.lookAt(state.target);
        const t0 = performance.now();
        renderer.render(scene, camera);
        renderer.getContext().finish();
        draws.push(performance.now() - t0);
        requestAnimationFrame(step);
      };
      requestAnimationFrame(step);
    });
  }

  return {
    show, go, settingsChanged, measure, state,
    box: (i) => (state.bvh ? box(state.bvh, i) : null),
    nodeInfo: (i) => (state.bvh ? {box: box(state.bvh, i), primitives: state.bvh.hi[i] - state.bvh.lo[i],
                                   depth: state.bvh.depth[i], rays: state.bvh.entered[i]} : null),
    view, orbit, zoom, redraw, moving,
    // Debug mode (debug3d.js) draws its rays into this scene.
    three: {scene, camera, redraw},
  };
}
