// The 3D modes: the camera (a rasterised preview to orbit, pan and zoom,
// "render from here", "save camera") and the BVH walk (the current node's
// box, its children's boxes, its primitives, a depth slider). three.js
// draws; the scene's triangles and the BVH come from the server, the BVH
// built by the build's own part 2 code in a worker.
import * as THREE from 'three';

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

  // Shading of a triangle soup, baked: 0.3 + 0.7 |n . l| for a light from
  // above and in front, times `rgb(t)` per triangle.
  const LIGHT = new THREE.Vector3(0.35, 0.8, 0.5).normalize();
  function bakedColors(pos, rgb) {
    const n = pos.length / 9, out = new Float32Array(n * 9);
    const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
    for (let t = 0; t < n; ++t) {
      a.fromArray(pos, 9 * t);
      b.fromArray(pos, 9 * t + 3).sub(a);
      c.fromArray(pos, 9 * t + 6).sub(a);
      const nrm = b.cross(c);
      const len = nrm.length();
      const k = 0.3 + 0.7 * (len > 0 ? Math.abs(nrm.dot(LIGHT)) / len : 0);
      const [r, g, bl] = rgb(t);
      for (let v = 0; v < 3; ++v) out.set([r * k, g * k, bl * k], 9 * t + 3 * v);
    }
    return out;
  }

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

  function fitCanvas() {
    const s = viewer.settings;
    const maxW = Math.max(320, Math.min(960, window.innerWidth - 320)), maxH = Math.max(240, window.innerHeight - 160);
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
    const sph = new Float32Array(buf, 8 + nt * 36, ns * 4);
    const rgb = new Uint8Array(buf, 8 + nt * 36 + ns * 16, (nt + ns) * 3);
    groups.camera.clear();
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(tris, 3));
    const colors = bakedColors(tris, (t) => [rgb[3 * t] / 255, rgb[3 * t + 1] / 255, rgb[3 * t + 2] / 255]);
    geo.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    groups.camera.add(new THREE.Mesh(geo, baseMaterial));
    const sphereGeo = new THREE.SphereGeometry(1, 32, 16);
    for (let i = 0; i < ns; ++i) {
      const c = 3 * (nt + i);
      const m = new THREE.Mesh(sphereGeo, sphereMaterial([rgb[c] / 255, rgb[c + 1] / 255, rgb[c + 2] / 255]));
      m.position.set(sph[4 * i], sph[4 * i + 1], sph[4 * i + 2]);
      m.scale.setScalar(sph[4 * i + 3]);
      groups.camera.add(m);
    }
    state.meshes = {tris, sph, nt, ns, sphereGeo};
    state.sceneKey = key;
  }

  // ------------------------------------------------------------ camera controls

  // While the camera moves, frames are drawn at half resolution (a quarter
  // of the pixels); the full view comes back when it stops.
  function moving(on) {
    const ratio = on ? 0.5 : 1;
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

  function orbit(dx, dy) {
    const offset = camera.position.clone().sub(state.target);
    const up = camera.up.clone().normalize();
    offset.applyAxisAngle(up, -dx * 0.005);
    const right = new THREE.Vector3().crossVectors(up, offset).normalize();
    const tilted = offset.clone().applyAxisAngle(right, dy * 0.005);
    // Stay off the poles, where the view would flip.
    if (Math.abs(tilted.clone().normalize().dot(up)) < 0.98) offset.copy(tilted);
    camera.position.copy(state.target).add(offset);
    camera.lookAt(state.target);
    redraw();
  }
  function pan(dx, dy) {
    const dist = camera.position.distanceTo(state.target);
    const k = 2 * dist * Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) / canvas.clientHeight;
    const right = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 0);
    const upv = new THREE.Vector3().setFromMatrixColumn(camera.matrix, 1);
    const move = right.multiplyScalar(-dx * k).add(upv.multiplyScalar(dy * k));
    camera.position.add(move);
    state.target.add(move);
    camera.lookAt(state.target);
    redraw();
  }
  function zoom(f) {
    const offset = camera.position.clone().sub(state.target).multiplyScalar(f);
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
    while (st.state === 'running') st = await hooks.api(`/api/status?job=${st.job}&after=0`);
    if (st.state !== 'done') {
      $('bvh-info').textContent = '';
      const lines = [st.message];
      if (st.todo.length) lines.push(hooks.todoText(st.todo));
      hooks.banner(lines.filter(Boolean).join('\n'), 'error');
      return null;
    }
    if (st.todo.length) hooks.banner(hooks.todoText(st.todo), 'todo');
    const res = await hooks.api(`/api/bvh-data?job=${st.job}`);
    const buf = await res.arrayBuffer();
    const headLen = new Uint32Array(buf, 0, 1)[0];
    const head = JSON.parse(new TextDecoder().decode(new Uint8Array(buf, 4, headLen)));
    const body = buf.slice(4 + headLen);
    const n = head.nodes, np = head.prims;
    const f = new Float32Array(body, 0, n * 8), u = new Uint32Array(body, 0, n * 8);
    const prims = new Uint32Array(body, n * 32, np);
    const entered = new Uint32Array(body, n * 32 + np * 4, n);
    const bvh = {head, n, f, u, prims, entered, parent: new Int32Array(n).fill(-1), depth: new Int32Array(n).fill(-1),
                 lo: new Uint32Array(n), hi: new Uint32Array(n), sah: new Float64Array(n), order: []};
    // Breadth first from the root: parents, depths, and an order to walk back up.
    if (n > 0) {
      bvh.depth[0] = 0;
      const queue = [0];
      for (let qi = 0; qi < queue.length; ++qi) {
        const i = queue[qi];
        bvh.order.push(i);
        if (u[8 * i + 7] === 0) {
          for (const c of [u[8 * i + 3], u[8 * i + 3] + 1]) {
            if (c < n && bvh.depth[c] < 0) {
              bvh.parent[c] = i;
              bvh.depth[c] = bvh.depth[i] + 1;
              queue.push(c);
            }
          }
        }
      }
    }
    bvh.maxDepth = 0;
    for (let k = bvh.order.length - 1; k >= 0; --k) {
      const i = bvh.order[k];
      bvh.maxDepth = Math.max(bvh.maxDepth, bvh.depth[i]);
      const count = u[8 * i + 7];
      if (count) {
        bvh.lo[i] = u[8 * i + 3];
        bvh.hi[i] = u[8 * i + 3] + count;
        bvh.sah[i] = count;
      } else {
        const l = u[8 * i + 3], r = l + 1;
        bvh.lo[i] = Math.min(bvh.lo[l], bvh.lo[r]);
        bvh.hi[i] = Math.max(bvh.hi[l], bvh.hi[r]);
        const a = area(bvh, i);
        bvh.sah[i] = 1 + (a > 0 ? (area(bvh, l) * bvh.sah[l] + area(bvh, r) * bvh.sah[r]) / a : 0);
      }
    }
    buildLeafOrderMesh(bvh);
    state.bvh = bvh;
    state.bvhKey = key;
    state.node = 0;
    $('depth-slider').max = bvh.maxDepth;
    $('depth-slider').value = -1;
    state.depthShown = -1;
    return bvh;
  }

  function box(bvh, i) {
    const f = bvh.f;
    return {lo: [f[8 * i], f[8 * i + 1], f[8 * i + 2]], hi: [f[8 * i + 4], f[8 * i + 5], f[8 * i + 6]]};
  }
  function area(bvh, i) {
    const b = box(bvh, i);
    const e = [0, 1, 2].map((k) => Math.max(0, b.hi[k] - b.lo[k]));
    return 2 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
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
    const pos = new Float32Array(count * 9);
    let t = 0;
    for (let k = 0; k < bvh.prims.length; ++k) {
      const id = bvh.prims[k];
      if (id < nt) pos.set(tris.subarray(9 * id, 9 * id + 9), 9 * t++);
    }
    bvh.triBefore = triBefore;
    groups.bvh.clear();
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    geo.setAttribute('color', new THREE.BufferAttribute(bakedColors(pos, () => [1, 1, 1]), 3));
    // One mesh, each triangle drawn once: the node's range (orange) and the
    // rest (grey) are two groups of the same buffer.
    bvh.highlight = new THREE.Mesh(geo, [dimMaterial, hiMaterial]);
    bvh.triangles = count;
    groups.bvh.add(bvh.highlight);
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
  function boxLines(bvh, nodes, color) {
    const pos = new Float32Array(nodes.length * 72);
    let o = 0;
    for (const i of nodes) {
      const b = box(bvh, i);
      const corner = (c) => [(c & 1 ? b.hi : b.lo)[0], (c & 2 ? b.hi : b.lo)[1], (c & 4 ? b.hi : b.lo)[2]];
      for (const [a, c] of EDGES) {
        pos.set(corner(a), o);
        pos.set(corner(c), o + 3);
        o += 6;
      }
    }
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    return new THREE.LineSegments(geo, new THREE.LineBasicMaterial({color, depthTest: false, transparent: true}));
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
    if (state.depthShown >= 0) {
      const at = [];
      for (let k = 0; k < bvh.n; ++k) if (bvh.depth[k] === state.depthShown) at.push(k);
      bvh.boxes.add(boxLines(bvh, at, 0xe6d84a));
    }
    bvh.boxes.add(boxLines(bvh, [i], 0xffffff));
    const kids = children(bvh, i);
    if (kids.length) {
      bvh.boxes.add(boxLines(bvh, [kids[0]], 0xff4d4d));
      bvh.boxes.add(boxLines(bvh, [kids[1]], 0x4da6ff));
    }
    const t0 = bvh.triBefore[bvh.lo[i]], t1 = bvh.triBefore[bvh.hi[i]];
    const g = bvh.highlight.geometry;
    g.clearGroups();
    if (t0 > 0) g.addGroup(0, t0 * 3, 0);
    if (t1 > t0) g.addGroup(t0 * 3, (t1 - t0) * 3, 1);
    if (bvh.triangles > t1) g.addGroup(t1 * 3, (bvh.triangles - t1) * 3, 0);
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
    let best = null;
    for (const [k, side] of children(bvh, state.node).map((c, j) => [c, j ? 'right' : 'left'])) {
      const b = box(bvh, k);
      const hit = ray.ray.intersectBox(new THREE.Box3(new THREE.Vector3(...b.lo), new THREE.Vector3(...b.hi)),
                                       new THREE.Vector3());
      if (hit) {
        const d = hit.distanceTo(camera.position);
        if (!best || d < best.d) best = {d, side};
      }
    }
    if (best) go(best.side);
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
      const times = [];
      let last = 0, k = 0;
      const step = (t) => {
        if (last) times.push(t - last);
        last = t;
        if (k++ >= frames) {
          moving(false);
          resolve(times);
          return;
        }
        const offset = camera.position.clone().sub(state.target).applyAxisAngle(camera.up, 0.01);
        camera.position.copy(state.target).add(offset);
        camera.lookAt(state.target);
        renderer.render(scene, camera);
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
    view, orbit, zoom, redraw,
  };
}
