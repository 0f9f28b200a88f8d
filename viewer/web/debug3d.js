// Debug mode's 3D drawing: lines, arrows, points and outlines in a group of
// their own, added to the scene of the 3D view (view3d.js's `three`).
import * as THREE from 'three';

export const COLORS = {
  camera: 0xffffff, bounce: 0x4fc3f7, shadow: 0xffe14f, shadow_blocked: 0xff4f4f, probe: 0xb388ff,
  ray: 0xffffff, hit: 0x7cff6b, normal: 0x7cff6b, shape: 0xff9a2e, light: 0xffe14f, sample: 0xffe14f,
  point: 0x4fc3f7, untested: 0x8a8a8a,
};

// Lines on top of the scene (no depth test), so that a ray inside a box stays visible.
function lineMaterial(color) {
  return new THREE.LineBasicMaterial({color, depthTest: false, transparent: true, opacity: 0.95});
}

export function createOverlay(three) {
  const group = new THREE.Group();
  group.renderOrder = 10;
  three.scene.add(group);
  const v = (a) => new THREE.Vector3(a[0], a[1], a[2]);

  const api = {
    group,
    clear() {
      for (const c of [...group.children]) {
        group.remove(c);
        if (c.geometry) c.geometry.dispose();
      }
    },
    // Line segments: pairs [[from, to], ...] of one colour.
    segments(pairs, color) {
      if (!pairs.length) return null;
      const pos = new Float32Array(pairs.length * 6);
      pairs.forEach(([a, b], i) => pos.set([...a, ...b], 6 * i));
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
      const line = new THREE.LineSegments(geo, lineMaterial(color));
      line.renderOrder = 10;
      group.add(line);
      return line;
    },
    // An arrow from `from` along `dir` of length `len`.
    arrow(from, dir, len, color) {
      const d = v(dir);
      if (!(d.length() > 0)) return null;
      const a = new THREE.ArrowHelper(d.normalize(), v(from), len, color, len * 0.25, len * 0.12);
      a.traverse((o) => { if (o.material) { o.material.depthTest = false; o.renderOrder = 11; } });
      group.add(a);
      return a;
    },
    // Points drawn as small squares of `size` pixels.
    points(list, color, size = 6) {
      if (!list.length) return null;
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(list.flat()), 3));
      const p = new THREE.Points(geo, new THREE.PointsMaterial({color, size, sizeAttenuation: false, depthTest: false}));
      p.renderOrder = 12;
      group.add(p);
      return p;
    },
    // A closed polygon's outline.
    loop(corners, color) {
      const pairs = corners.map((c, i) => [c, corners[(i + 1) % corners.length]]);
      return api.segments(pairs, color);
    },
    // A sphere as three great circles.
    sphere(center, radius, color) {
      const pairs = [];
      const n = 48;
      for (let axis = 0; axis < 3; ++axis) {
        for (let i = 0; i < n; ++i) {
          const at = (k) => {
            const a = (2 * Math.PI * k) / n, p = [0, 0, 0];
            p[(axis + 1) % 3] = Math.cos(a) * radius;
            p[(axis + 2) % 3] = Math.sin(a) * radius;
            return [center[0] + p[0], center[1] + p[1], center[2] + p[2]];
          };
          pairs.push([at(i), at(i + 1)]);
        }
      }
      return api.segments(pairs, color);
    },
    redraw: three.redraw,
  };
  return api;
}
