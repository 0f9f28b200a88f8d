// The server without a page, as another program (or another site) would
// talk to it: the token, the folders, bad requests.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import {args, check, rawRequest, startViewer, stopViewer, tryStartViewer, SCENE, memoryMB, resetPeakMemory, postJson,
        jobEnd, workersOf} from './harness.mjs';

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
    const post = (body) => fetch(`${v.base}/api/render`, {method: 'POST', body,
                                                            headers: {'X-Token': v.token, 'Content-Type': 'application/json'}});
    for (const [what, scene] of [['a path with ..', `${dir}/../${path.basename(outside)}/secret.dae`],
                                 ['an absolute path elsewhere', path.join(outside, 'secret.dae')],
                                 ['/etc/passwd', '/etc/passwd'],
                                 ['a symlink out of the folder', path.join(dir, 'link.dae')]]) {
      const res = await post(JSON.stringify({scene}));
      const body = await res.json();
      check(res.status === 403 && /not a file the viewer may open/.test(body.error), `${what} is refused`, `${res.status} ${body.error}`);
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

const renderWorkers = (v) => workersOf(v, 'render');

// Ten render requests at once (long renders, each its own seed): when all
// are answered, one render worker is left (the last request's); Stop
// answers once it is gone too, and none is left.
cases.concurrent_renders = async () => {
  const v = await startViewer(args.viewer, ['-r', '64', '48', '-s', '4096', '-m', '8', '-t', '4', SCENE()]);
  try {
    const post = (p, body) => rawRequest(v, {method: 'POST', path: p, body: JSON.stringify(body),
                                               headers: {'X-Token': v.token, 'Content-Type': 'application/json'}});
    const answers = await Promise.all([...Array(10).keys()].map((i) => post('/api/render', {seed: 100 + i})));
    const jobs = answers.map((a) => (a.status === 200 ? JSON.parse(a.body).job : null));
    check(jobs.every((j) => j !== null), 'the ten render requests are answered', answers.map((a) => a.status).join());
    const left = renderWorkers(v);
    check(left.length <= 1, 'one render worker at most is alive once all ten are answered',
          `${left.length}: ${left.map((c) => c.cmd.replace(/.* --seed (\d+) .*/, 'seed $1')).join(', ')}`);
    const last = Math.max(...jobs);
    const st = JSON.parse((await rawRequest(v, {path: `/api/status?job=${last}&token=${v.token}`})).body);
    check(left.length === 1 && left[0].cmd.includes(` --seed ${st.settings.seed} `) && st.state === 'running',
          'it is the newest job\'s', JSON.stringify({seed: st.settings.seed, state: st.state}));
    const stop = await post('/api/stop', {});
    check(stop.status === 200, '/api/stop answers', String(stop.status));
    const after = renderWorkers(v);
    check(after.length === 0, 'after Stop no render worker is left',
          after.map((c) => c.cmd.replace(/.* --seed (\d+) .*/, 'seed $1')).join(', '));
    const ended = JSON.parse((await rawRequest(v, {path: `/api/status?job=${last}&token=${v.token}`})).body);
    check(ended.state === 'cancelled', 'the newest job is cancelled', ended.state);
  } finally {
    await stopViewer(v);
  }
};

// What a page of another site (another port of 127.0.0.1, or a name made
// to point at it) can make a browser send is refused, even with the
// page's cookie: a text/plain or form body, another Origin, Sec-Fetch-Site
// same-site or cross-site, another Host. No job starts; the viewer's own
// page's requests (JSON, its Origin, same-origin) go on.
cases.cross_site = async () => {
  const v = await startViewer(args.viewer, ['-r', '32', '24', '-s', '1', SCENE()]);
  try {
    const cookie = `pt_viewer_${v.port}=${v.token}`;
    const body = JSON.stringify({seed: 3});
    const attempts = [
      ['a text/plain body (a "no-cors" fetch)', {'Content-Type': 'text/plain;charset=UTF-8', Cookie: cookie}, 415],
      ['a form post', {'Content-Type': 'application/x-www-form-urlencoded', Cookie: cookie}, 415],
      ['JSON with another port\'s Origin', {'Content-Type': 'application/json', Cookie: cookie,
                                            Origin: `http://127.0.0.1:${v.port + 1}`}, 403],
      ['JSON with Sec-Fetch-Site: same-site', {'Content-Type': 'application/json', Cookie: cookie,
                                               'Sec-Fetch-Site': 'same-site'}, 403],
      ['JSON with Sec-Fetch-Site: cross-site', {'Content-Type': 'application/json', 'X-Token': v.token,
                                                'Sec-Fetch-Site': 'cross-site'}, 403],
      ['a request for evil.example (DNS rebinding)', {'Content-Type': 'application/json', 'X-Token': v.token,
                                                      Host: `evil.example:${v.port}`}, 403],
      ['the old cookie name', {'Content-Type': 'application/json', Cookie: `pt_viewer_token=${v.token}`}, 403],
    ];
    for (const [what, headers, status] of attempts) {
      const r = await rawRequest(v, {method: 'POST', path: '/api/render', headers, body});
      let reason = '';
      try { reason = JSON.parse(r.body).error; } catch (e) { reason = r.body; }
      check(r.status === status && /^refused: /.test(reason), `${what}: refused with ${status} and the reason`,
            `${r.status} ${r.body.slice(0, 200)}`);
    }
    const get = await rawRequest(v, {path: `/api/state?token=${v.token}`, headers: {Host: 'evil.example'}});
    check(get.status === 403, 'a GET for evil.example is refused too', String(get.status));
    const page = await rawRequest(v, {path: '/', headers: {Cookie: cookie, 'Sec-Fetch-Site': 'same-site'}});
    check(page.status === 403, 'another port\'s page cannot open the viewer\'s page with the cookie alone', String(page.status));
    // The viewer's own page: JSON, its Origin, same-origin, its cookie.
    const own = await rawRequest(v, {method: 'POST', path: '/api/render', body,
                                     headers: {'Content-Type': 'application/json', Cookie: cookie,
                                               Origin: `http://127.0.0.1:${v.port}`, 'Sec-Fetch-Site': 'same-origin'}});
    check(own.status === 200 && JSON.parse(own.body).job === 1,
          'the page\'s own request starts a render, job 1: none of the refused ones started a job', `${own.status} ${own.body.slice(0, 80)}`);
  } finally {
    await stopViewer(v);
  }
};

// Forty status requests waiting on a render that makes no progress (the
// test build's planted endless loop) do not take every thread of the
// server: those beyond its limit are answered at once ("busy"), and a
// request for /api/state is answered while the others still wait.
cases.long_polls = async () => {
  const v = await startViewer(args.planted, ['-r', '32', '24', '-s', '1', '--seed', '15', SCENE()], {PT_VIEWER_PLANT: 'hang'});
  try {
    const r = await rawRequest(v, {method: 'POST', path: '/api/render', body: '{}',
                                   headers: {'X-Token': v.token, 'Content-Type': 'application/json'}});
    const job = JSON.parse(r.body).job;
    const order = [];
    const polls = [...Array(40).keys()].map((i) =>
      rawRequest(v, {path: `/api/status?job=${job}&after=0&token=${v.token}`}).then((a) => {
        const st = JSON.parse(a.body);
        order.push(st.busy ? 'busy' : `poll ${st.state}`);
        return st;
      }));
    // Every poll beyond the limit is answered at once; then /api/state.
    const busy = await new Promise((resolve) => {
      let n = 0;
      for (const p of polls) p.then((st) => { if (st.busy && ++n === 24) resolve(n); });
      Promise.all(polls).then(() => resolve(n));
    });
    check(busy === 24, 'the 24 status requests beyond the 16 that may wait are answered at once ("busy")', String(busy));
    const state = await rawRequest(v, {path: `/api/state?token=${v.token}`});
    order.push(`state ${state.status}`);
    check(state.status === 200 && !order.slice(0, order.indexOf(`state ${state.status}`)).some((x) => x.startsWith('poll')),
          '/api/state is answered while the 16 others still wait', order.join(', '));
    await rawRequest(v, {method: 'POST', path: '/api/stop', body: '{}',
                         headers: {'X-Token': v.token, 'Content-Type': 'application/json'}});
    const all = await Promise.all(polls);
    check(all.filter((st) => !st.busy).every((st) => st.state === 'cancelled'),
          'Stop ends the render and answers the waiting ones', all.map((st) => st.state).join());
  } finally {
    await stopViewer(v);
  }
};

// Camera files (-c) from the page: only files with the course's six lines
// of numbers are read (the renderer's errors would quote any other file),
// and a missing file and one outside the folders get the same answer.
cases.camera_files = async () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'pt-viewer-cameras-'));
  fs.copyFileSync(SCENE(), path.join(dir, 'scene.dae'));
  fs.writeFileSync(path.join(dir, 'notes'), 'SECRET_WORD=swordfish\n');
  fs.writeFileSync(path.join(dir, 'camera.txt'),
                   ['30 22.5 1.333 0.1 100', '0 1 4 0 1 0', '1.57 0 4 0.4 40', '1 0 0 0 1 0 0 0 1', '480 360 1', '4 0']
                     .join('\n') + '\n');
  // Allowed everywhere (as --allow / would): still only camera files.
  const v = await startViewer(args.viewer, ['--allow', '/', '-r', '32', '24', path.join(dir, 'scene.dae')]);
  try {
    const ask = async (camera_file) => {
      const r = await rawRequest(v, {method: 'POST', path: '/api/scene', body: JSON.stringify({camera_file}),
                                     headers: {'X-Token': v.token, 'Content-Type': 'application/json'}});
      return {status: r.status, error: r.status === 200 ? '' : JSON.parse(r.body).error};
    };
    const environ = await ask('/proc/self/environ');
    check(environ.status === 403 && !/=/.test(environ.error.replace('/proc/self/environ', '')),
          '/proc/self/environ is not a camera file, and nothing of it is quoted', JSON.stringify(environ));
    const notes = await ask(path.join(dir, 'notes'));
    check(notes.status === 403 && !notes.error.includes('SECRET') && /not a camera settings file/.test(notes.error),
          'an extension-less text file is not a camera file, and nothing of it is quoted', JSON.stringify(notes));
    const good = await ask(path.join(dir, 'camera.txt'));
    check(good.status === 200, 'a file in the course\'s six-line format is read', JSON.stringify(good));
    // Outside the folders: missing or there, the same answer.
    const v2 = await startViewer(args.viewer, ['-r', '32', '24', path.join(dir, 'scene.dae')]);
    try {
      const ask2 = async (camera_file) => {
        const r = await rawRequest(v2, {method: 'POST', path: '/api/render', body: JSON.stringify({camera_file}),
                                        headers: {'X-Token': v2.token, 'Content-Type': 'application/json'}});
        return {status: r.status, error: JSON.parse(r.body).error || ''};
      };
      const state = JSON.parse((await rawRequest(v2, {path: `/api/state?token=${v2.token}`})).body);
      check(JSON.stringify(state.cameras) === JSON.stringify([fs.realpathSync(path.join(dir, 'camera.txt'))]),
            'the page lists camera.txt as a camera file, and not notes', JSON.stringify(state.cameras));
      const there = await ask2('/etc/hostname'), missing = await ask2('/etc/no-such-file-here');
      check(there.status === missing.status &&
            there.error.replace('/etc/hostname', 'X') === missing.error.replace('/etc/no-such-file-here', 'X'),
            'a file outside the folders and a missing one get the same answer', JSON.stringify([there, missing]));
    } finally {
      await stopViewer(v2);
    }
  } finally {
    await stopViewer(v);
    fs.rmSync(dir, {recursive: true, force: true});
  }
};

// The server's memory stays bounded: three renders in a row keep one
// render's image (20 bytes a pixel), not three, and six clients
// downloading its PFM or its PNG at once cost at most one more image
// (the PFM is streamed, PNGs are made one at a time). 2048x1024, part 1:
// an image is 40 MiB.
cases.memory_bound = async () => {
  const frameMB = 2048 * 1024 * 20 / (1 << 20);
  const v = await startViewer(args.viewer, ['--part', '1', '-r', '2048', '1024', '-s', '1', '-t', '2', SCENE()]);
  try {
    const rss = [];
    let job = null;
    for (let i = 0; i < 3; ++i) {
      job = (await postJson(v, '/api/render', {seed: i})).json.job;
      const end = await jobEnd(v, job);
      check(end.state === 'done', `render ${i + 1} of 3 finishes`, end.state);
      rss.push(memoryMB(v.proc.pid).rss);
    }
    check(rss[2] - rss[0] <= frameMB / 2, `after three renders the server holds one image: ${rss.join(' -> ')} MB (an image: ${frameMB} MB)`,
          `${rss[2] - rss[0]} MB more after the third than after the first`);
    for (const [kind, bound] of [['pfm', frameMB / 2], ['png', frameMB]]) {
      resetPeakMemory(v.proc.pid);
      const before = memoryMB(v.proc.pid).rss;
      const got = await Promise.all([...Array(6).keys()].map(() =>
        rawRequest(v, {path: `/api/${kind}?job=${job}&token=${v.token}`, discard: true})));
      const peak = memoryMB(v.proc.pid).peak;
      check(got.every((g) => g.status === 200 && g.bytes === got[0].bytes && g.bytes > 0), `six ${kind.toUpperCase()} downloads at once are answered`,
            got.map((g) => `${g.status}/${g.bytes}`).join());
      check(peak - before <= bound, `their peak is at most ${bound} MB above the ${before} MB before them`, `peak ${peak} MB`);
    }
  } finally {
    await stopViewer(v);
  }
};
