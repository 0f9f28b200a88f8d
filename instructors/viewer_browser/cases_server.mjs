// The server without a page, as another program (or another site) would
// talk to it: the token, the folders, bad requests.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import {args, check, rawRequest, startViewer, stopViewer, tryStartViewer, SCENE} from './harness.mjs';

export const cases = {};

// Requests without the token are refused; files outside the folders named
// on the command line cannot be opened; bad requests get a 4xx.
cases.token_and_paths = async () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'pt-viewer-paths-'));
  const outside = fs.mkdtempSync(path.join(os.tmpdir(), 'pt-viewer-outside-'));
  fs.copyFileSync(SCENE(), path.join(dir, 'scene.dae'));
  fs.copyFileSync(SCENE(), path.join(outside, 'secret.dae'));
  fs.symlinkSync(path.join(outside, 'secret.dae'), path.join(dir, 'link.dae'));
  const v = await startViewer(args.viewer, ['-r', '32', '24', path.join(dir, 'scene.dae')]);
  try {
    for (const p of ['/', '/api/state', '/web/app.js', '/three/three.module.js', '/api/status?job=1']) {
      const res = await fetch(`${v.base}${p}`);
      check(res.status === 403, `${p} without the token is refused (403)`, String(res.status));
    }
    const wrong = await fetch(`${v.base}/api/state?token=${'0'.repeat(32)}`);
    check(wrong.status === 403, 'a wrong token is refused (403)', String(wrong.status));
    const ok = await fetch(`${v.base}/api/state?token=${v.token}`);
    check(ok.status === 200, 'the token of the printed URL is accepted', String(ok.status));
    const post = (body) => fetch(`${v.base}/api/render`, {method: 'POST', headers: {'X-Token': v.token}, body});
    for (const [what, scene] of [['a path with ..', `${dir}/../${path.basename(outside)}/secret.dae`],
                                 ['an absolute path elsewhere', path.join(outside, 'secret.dae')],
                                 ['/etc/passwd', '/etc/passwd'],
                                 ['a symlink out of the folder', path.join(dir, 'link.dae')]]) {
      const res = await post(JSON.stringify({scene}));
      const body = await res.json();
      check(res.status === 403 && /outside the folders/.test(body.error), `${what} is refused`, `${res.status} ${body.error}`);
    }
    for (const [what, body, status] of [['malformed JSON', '{"samples": ', 400],
                                        ['negative samples', '{"samples": -4}', 400],
                                        ['an absurd size', '{"width": 100000, "height": 100000}', 400],
                                        ['a fractional count', '{"threads": 1.5}', 400],
                                        ['a cell outside the image', '{"cell": [30, 0, 10, 10]}', 400],
                                        ['a body of a megabyte', `{"scene": "${'x'.repeat(1 << 20)}"}`, 413]]) {
      const res = await post(body);
      check(res.status === status, `${what} gets ${status}`, String(res.status));
    }
    const alive = await fetch(`${v.base}/api/state?token=${v.token}`);
    check(alive.status === 200, 'the server still serves after the bad requests');
  } finally {
    await stopViewer(v);
    fs.rmSync(dir, {recursive: true, force: true});
    fs.rmSync(outside, {recursive: true, force: true});
  }
};

// A port another viewer listens on is refused: the second viewer says so
// and exits, and the first one keeps answering every request.
cases.port_in_use = async () => {
  const first = await startViewer(args.viewer, ['-r', '32', '24', SCENE()]);
  try {
    const second = await tryStartViewer(args.viewer, ['--port', String(first.port), '-r', '32', '24', SCENE()]);
    if (second.v) await stopViewer(second.v);
    check(!second.v && second.code === 1, `a second viewer on port ${first.port} exits with status 1`,
          second.v ? `it started: ${second.v.url}` : `exit status ${second.code}`);
    check(!second.v && second.stderr.includes(`viewer: error: cannot listen on 127.0.0.1:${first.port} (in use?)`),
          'it says the port is in use', second.v ? '' : second.stderr);
    let answered = 0;
    for (let i = 0; i < 8; ++i) {
      const r = await rawRequest(first, {path: `/api/state?token=${first.token}`});
      if (r.status === 200) ++answered;
    }
    check(answered === 8, 'the first viewer answers every request on its port', `${answered} of 8`);
  } finally {
    await stopViewer(first);
  }
};
