// The BVH as the page walks it: /api/bvh-data's bytes read into arrays
// (nodes, leaf primitives, camera rays per node), each node's parent,
// depth, primitive range and SAH cost; a node's box and its area; a ray
// against a box (view3d.js).

// uint32 length of the JSON head, the head, then the nodes (32 bytes
// each: lo, first, hi, count), the leaf primitives and the rays per node.
export function parseBVH(buf) {
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
  return bvh;
}

export function box(bvh, i) {
  const f = bvh.f;
  return {lo: [f[8 * i], f[8 * i + 1], f[8 * i + 2]], hi: [f[8 * i + 4], f[8 * i + 5], f[8 * i + 6]]};
}
export function area(bvh, i) {
  const b = box(bvh, i);
  const e = [0, 1, 2].map((k) => Math.max(0, b.hi[k] - b.lo[k]));
  return 2 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
}

// Where a ray enters and leaves a box ({enter, leave}, distances along
// the ray from its origin, enter 0 when it starts inside), or null when it
// misses the box.
export function raySpan(r, b) {
  let enter = 0, leave = Infinity;
  for (const [k, axis] of [[0, 'x'], [1, 'y'], [2, 'z']]) {
    const o = r.origin[axis], d = r.direction[axis];
    if (d === 0) {
      if (o < b.lo[k] || o > b.hi[k]) return null;
      continue;
    }
    let t0 = (b.lo[k] - o) / d, t1 = (b.hi[k] - o) / d;
    if (t0 > t1) [t0, t1] = [t1, t0];
    enter = Math.max(enter, t0);
    leave = Math.min(leave, t1);
  }
  return enter <= leave ? {enter, leave} : null;
}
