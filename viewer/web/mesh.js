// The 3D views' meshes: the scene's triangles as an indexed mesh with its
// lighting baked into vertex colours, and the coarse copy drawn while the
// camera moves (view3d.js).
import * as THREE from 'three';

// Meshes above this many triangles get a coarse copy drawn while the
// camera moves (software WebGL draws about 2-3 million triangles a second
// on these machines). The copy merges vertices on a grid of COARSE_CELLS
// per side: 48 leaves the 200,000-triangle dragon 5,674 triangles, which
// with the smaller drawing buffer while moving (view3d.js) keeps a moving
// frame within 16.7 ms.
const COARSE_ABOVE = 60000, COARSE_CELLS = 48;

// A coarse copy of an indexed mesh: vertices snapped to a grid of
// `cells` per side of its bounds and merged, triangles that collapse
// dropped, the rest kept in order. Returns the index array and, per kept
// triangle, its number in the full mesh.
export function coarseIndex(geo, cells) {
  const pos = geo.getAttribute('position').array, index = geo.index.array;
  const nv = pos.length / 3;
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let v = 0; v < nv; ++v) {
    for (let k = 0; k < 3; ++k) {
      lo[k] = Math.min(lo[k], pos[3 * v + k]);
      hi[k] = Math.max(hi[k], pos[3 * v + k]);
    }
  }
  const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;
  const cell = (x, k) => Math.min(cells - 1, Math.floor((x - lo[k]) / size * cells));
  const rep = new Int32Array(nv), seen = new Map();
  for (let v = 0; v < nv; ++v) {
    const key = (cell(pos[3 * v], 0) * cells + cell(pos[3 * v + 1], 1)) * cells + cell(pos[3 * v + 2], 2);
    const r = seen.get(key);
    if (r === undefined) seen.set(key, v);
    rep[v] = r === undefined ? v : r;
  }
  const out = [], kept = [];
  for (let t = 0; t < index.length / 3; ++t) {
    const a = rep[index[3 * t]], b = rep[index[3 * t + 1]], c = rep[index[3 * t + 2]];
    if (a !== b && b !== c && a !== c) {
      out.push(a, b, c);
      kept.push(t);
    }
  }
  return {index: new Uint32Array(out), kept: new Uint32Array(kept)};
}

// The coarse mesh of `full` (same vertices and material), or null for a
// small mesh.
export function coarseMesh(full) {
  const geo = full.geometry;
  if (geo.index.count / 3 <= COARSE_ABOVE) return null;
  const c = coarseIndex(geo, COARSE_CELLS);
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', geo.getAttribute('position'));
  g.setAttribute('color', geo.getAttribute('color'));
  g.setIndex(new THREE.BufferAttribute(c.index, 1));
  const m = new THREE.Mesh(g, full.material);
  m.userData.kept = c.kept;
  m.visible = false;
  return m;
}

// The baked lighting's direction: from above and in front.
const LIGHT = new THREE.Vector3(0.35, 0.8, 0.5).normalize();

// A triangle soup as an indexed mesh: corners with the same position,
// shading normal and key(triangle) become one vertex, so that each is
// transformed once (a smooth mesh shares each vertex among about six
// triangles). Its colour attribute holds the baked shade
// 0.3 + 0.7 |n . l| of the vertex normal; userData.owner[v] is a
// triangle that uses vertex v.
export function indexedMesh(pos, nrm, key) {
  const n = pos.length / 9, pu = new Uint32Array(pos.buffer, pos.byteOffset, pos.length);
  const nu = new Uint32Array(nrm.buffer, nrm.byteOffset, nrm.length);
  let cap = 1;
  while (cap < n * 6) cap *= 2;
  const table = new Int32Array(cap).fill(-1);
  const outP = new Float32Array(n * 9), outN = new Float32Array(n * 9);
  const outPU = new Uint32Array(outP.buffer), outNU = new Uint32Array(outN.buffer);
  const owner = new Int32Array(n * 3), keys = new Int32Array(n * 3);
  const index = new Uint32Array(n * 3);
  let count = 0;
  for (let c = 0; c < n * 3; ++c) {
    const t = (c / 3) | 0, kt = key(t);
    const a = pu[3 * c], b = pu[3 * c + 1], d = pu[3 * c + 2];
    const e = nu[3 * c], f = nu[3 * c + 1], g = nu[3 * c + 2];
    let h = Math.imul(a ^ Math.imul(b, 0x85ebca6b) ^ Math.imul(d, 0xc2b2ae35), 0x9e3779b1);
    h = Math.imul(h ^ e ^ Math.imul(f, 0x27d4eb2f) ^ Math.imul(g, 0x165667b1) ^ kt, 0x9e3779b1);
    let slot = (h >>> 7) & (cap - 1);
    for (;;) {
      const v = table[slot];
      if (v < 0) {
        table[slot] = count;
        outPU.set([a, b, d], 3 * count);
        outNU.set([e, f, g], 3 * count);
        owner[count] = t;
        keys[count] = kt;
        index[c] = count++;
        break;
      }
      if (outPU[3 * v] === a && outPU[3 * v + 1] === b && outPU[3 * v + 2] === d && outNU[3 * v] === e &&
          outNU[3 * v + 1] === f && outNU[3 * v + 2] === g && keys[v] === kt) {
        index[c] = v;
        break;
      }
      slot = (slot + 1) & (cap - 1);
    }
  }
  const shade = new Float32Array(count * 3);
  for (let v = 0; v < count; ++v) {
    const x = outN[3 * v], y = outN[3 * v + 1], z = outN[3 * v + 2];
    const len = Math.hypot(x, y, z);
    const k = 0.3 + 0.7 * (len > 0 ? Math.abs(x * LIGHT.x + y * LIGHT.y + z * LIGHT.z) / len : 0);
    shade.set([k, k, k], 3 * v);
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(outP.slice(0, count * 3), 3));
  geo.setAttribute('color', new THREE.BufferAttribute(shade, 3));
  geo.setIndex(new THREE.BufferAttribute(index, 1));
  geo.userData.owner = owner.subarray(0, count);
  return geo;
}
