// The browser tests' harness: the command line's arguments, check() and
// its tally, starting and stopping viewers, a fresh headless Chromium per
// case, and the helpers the cases share (the page's event log, canvas and
// PNG pixels, the API with the token). Every wait is on an event of the
// page or a process, never a fixed delay.
import {spawn, spawnSync} from 'node:child_process';
import {createRequire} from 'node:module';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';

export const args = {};
for (let i = 2; i < process.argv.length; ++i) {
  const a = process.argv[i];
  if (a.startsWith('--')) {
    const next = process.argv[i + 1];
    args[a.slice(2)] = next === undefined || next.startsWith('--') ? true : (++i, next);
  }
}
export const OUT = path.resolve(args.out || 'viewer-artifacts');
fs.mkdirSync(OUT, {recursive: true});

let failures = 0, passes = 0;
export function check(ok, what, detail) {
  if (ok) {
    ++passes;
    console.log(`ok - ${what}`);
  } else {
    ++failures;
    console.log(`FAIL - ${what}${detail ? `: ${detail}` : ''}`);
  }
  return ok;
}

export function loadPlaywright() {
  const pkg = path.resolve(args.web, 'package.json');
  if (!fs.existsSync(path.join(args.web, 'node_modules', 'playwright-core'))) {
    console.log(`FAIL - playwright-core is not installed in ${args.web}/node_modules: run scripts/setup.sh (npm ci)`);
    process.exit(1);
  }
  return createRequire(pkg)('playwright-core');
}

// ------------------------------------------------------------- processes

const children = [];
process.on('exit', () => { for (const c of children) if (c.exitCode === null) c.kill('SIGKILL'); });

// Starts a viewer; resolves with how its start ended: {v} once it printed
// its URL (v as startViewer gives it), or {code, stderr} when it exited
// before that.
export function tryStartViewer(bin, flags, env) {
  return new Promise((resolve, reject) => {
    const proc = spawn(bin, flags, {env: Object.assign({}, process.env, env || {}), stdio: ['ignore', 'pipe', 'pipe']});
    children.push(proc);
    let out = '', err = '', started = false;
    const waiting = [];  // [regex, resolve] of waitStderr
    proc.stderr.on('data', (d) => {
      err += d;
      for (let i = waiting.length - 1; i >= 0; --i) {
        const m = waiting[i][0].exec(err);
        if (m) {
          waiting[i][1](m);
          waiting.splice(i, 1);
        }
      }
    });
    // Resolves with the match once the viewer's stderr matches `re`.
    const waitStderr = (re) => new Promise((resolve) => {
      const m = re.exec(err);
      if (m) resolve(m); else waiting.push([re, resolve]);
    });
    proc.stdout.on('data', (d) => {
      out += d;
      const line = out.split('\n')[0];
      if (out.includes('\n') && !started) {
        started = true;
        const m = /^(http:\/\/127\.0\.0\.1:(\d+))\/\?token=([0-9a-f]{32})$/.exec(line);
        if (m) resolve({v: {url: line, base: m[1], port: Number(m[2]), token: m[3], proc, stderr: () => err, waitStderr}});
        else reject(new Error(`unexpected first line: ${line}`));
      }
    });
    // 'close': after the exit and the end of both streams.
    proc.on('close', (code) => { if (!started) resolve({code, stderr: err}); });
  });
}

// Starts a viewer; resolves with {url, base, port, token, proc, stderr,
// waitStderr} once it printed its URL.
export async function startViewer(bin, flags, env) {
  const r = await tryStartViewer(bin, flags, env);
  if (!r.v) throw new Error(`viewer exited (${r.code}) before printing its URL: ${r.stderr}`);
  return r.v;
}

export function stopViewer(v) {
  return new Promise((resolve) => {
    if (v.proc.exitCode !== null) return resolve(v.proc.exitCode);
    v.proc.on('exit', (code, sig) => resolve(code === null ? sig : code));
    v.proc.kill('SIGINT');
  });
}

export function runCli(flags) {
  const r = spawnSync(args.pathtracer, flags, {encoding: 'utf8'});
  if (r.status !== 0) throw new Error(`pathtracer ${flags.join(' ')} failed: ${r.stderr}`);
  return r;
}

// ---------------------------------------------------------------- browser

export async function openBrowser() {
  const {chromium} = loadPlaywright();
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'pt-viewer-chromium-'));
  // A fresh profile (playwright passes it as --user-data-dir).
  const browser = await chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
    acceptDownloads: true,
    viewport: {width: 1400, height: 900},
  });
  const page = browser.pages()[0] || await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  return {browser, page, errors, close: async () => { await browser.close(); fs.rmSync(profile, {recursive: true, force: true}); }};
}

// Starts a viewer with `flags` (opts.bin: another build, default the
// viewer; opts.env: added to its environment), opens its page in a fresh
// headless Chromium, waits until the page is ready (opts.load === false:
// leaves the page blank, for the caller to time the load) and runs
// fn(page, v, errors): v is startViewer's, errors the page's script errors
// so far. Whatever fn does, the browser is closed and the viewer stopped.
export async function withViewerPage(flags, fn, opts = {}) {
  const v = await startViewer(opts.bin || args.viewer, flags, opts.env);
  try {
    const b = await openBrowser();
    try {
      if (opts.load !== false) {
        await b.page.goto(v.url);
        await b.page.waitForFunction(() => document.body.dataset.ready === '1');
      }
      return await fn(b.page, v, b.errors);
    } finally {
      await b.close();
    }
  } finally {
    await stopViewer(v);
  }
}

// Waits until the page's event log has an event matching `pred` (a function
// source over the event `e`) and returns it.
export async function waitEvent(page, pred, timeout = 60000) {
  const h = await page.waitForFunction(`window.viewer && window.viewer.events.find((e) => ${pred})`, null, {timeout});
  return h.jsonValue();
}
export const lastJob = (page) => page.evaluate(() => window.viewer.job);

export async function renderEnd(page, job, timeout) {
  return waitEvent(page, `e.type === 'end' && e.job === ${job}`, timeout);
}

// The render canvas's pixels, as an array of RGBA bytes.
export function canvasPixels(page) {
  return page.evaluate(() => {
    const c = document.getElementById('render-canvas');
    return Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data);
  });
}

// A PNG's pixels as the browser decodes it.
export function pngPixels(page, file) {
  const b64 = fs.readFileSync(file).toString('base64');
  return page.evaluate(async (data) => {
    const img = new Image();
    img.src = `data:image/png;base64,${data}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    return {w: img.width, h: img.height, data: Array.from(g.getImageData(0, 0, img.width, img.height).data)};
  }, b64);
}

export async function fetchBytes(v, p) {
  const res = await fetch(`${v.base}${p}`, {headers: {'X-Token': v.token}});
  if (!res.ok) throw new Error(`${p}: HTTP ${res.status}`);
  return Buffer.from(await res.arrayBuffer());
}

// One HTTP request to a viewer with exactly the headers given (Host,
// Origin and Content-Type included, which a browser's fetch would set
// itself), on its own connection. Resolves with {status, headers, body}
// (the body as text; with `discard`, only its length, as `bytes`).
export function rawRequest(v, {method = 'GET', path: p = '/', headers = {}, body, discard = false}) {
  return new Promise((resolve, reject) => {
    const req = http.request({host: '127.0.0.1', port: v.port, method, path: p, agent: false,
                              headers: Object.assign({Host: `127.0.0.1:${v.port}`}, headers)}, (res) => {
      const chunks = [];
      let bytes = 0;
      res.on('data', (c) => { bytes += c.length; if (!discard) chunks.push(c); });
      res.on('end', () => resolve({status: res.statusCode, headers: res.headers, bytes,
                                   body: discard ? '' : Buffer.concat(chunks).toString()}));
    });
    req.on('error', reject);
    if (body !== undefined) req.write(body);
    req.end();
  });
}

export function sameArrays(a, b) {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; ++i) if (a[i] !== b[i]) return false;
  return true;
}

export const SCENE = () => path.join(args.scenes, 'CBspheres_lambertian.dae');
// Small and quick, with every part's code in the loop (part 5, two bounces).
export const FLAGS = ['-r', '96', '72', '-s', '16', '-l', '1', '-m', '2', '-t', '2', '--seed', '5'];

// The tally of check() so far.
export function summary() {
  return {passes, failures};
}


// A process's resident memory and its peak since the last resetPeakMemory,
// in MB (/proc/PID/status).
export function memoryMB(pid) {
  const st = fs.readFileSync(`/proc/${pid}/status`, 'utf8');
  const kb = (key) => Number(new RegExp(`^${key}:\\s+(\\d+) kB`, 'm').exec(st)[1]);
  return {rss: Math.round(kb('VmRSS') / 1024), peak: Math.round(kb('VmHWM') / 1024)};
}
export function resetPeakMemory(pid) {
  fs.writeFileSync(`/proc/${pid}/clear_refs`, '5');
}

// POSTs `body` (JSON) to `p` with the token.
export async function postJson(v, p, body) {
  const r = await rawRequest(v, {method: 'POST', path: p, body: JSON.stringify(body),
                                 headers: {'X-Token': v.token, 'Content-Type': 'application/json'}});
  return {status: r.status, json: JSON.parse(r.body)};
}

// Waits (status long polls) until job `job` has ended; resolves with its status.
export async function jobEnd(v, job) {
  let st = {state: 'running', frames: 0};
  while (st.state === 'running') {
    const r = await rawRequest(v, {path: `/api/status?job=${job}&after=${st.frames}&token=${v.token}`});
    st = JSON.parse(r.body);
  }
  return st;
}

// The processes whose parent is `pid` and that are not zombies, with their
// command lines.
export function liveChildren(pid) {
  const out = [];
  for (const d of fs.readdirSync('/proc')) {
    if (!/^\d+$/.test(d)) continue;
    try {
      const stat = fs.readFileSync(`/proc/${d}/stat`, 'utf8');
      // "pid (comm) state ppid ...": the name may hold spaces and brackets.
      const [state, ppid] = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
      if (Number(ppid) !== pid || state === 'Z') continue;
      out.push({pid: Number(d), cmd: fs.readFileSync(`/proc/${d}/cmdline`, 'utf8').split('\0').join(' ')});
    } catch (e) { /* gone meanwhile */ }
  }
  return out;
}
// The viewer's live workers of a kind ("render" covers normals too, "debug", "bvh").
export const workersOf = (v, kind) => liveChildren(v.proc.pid).filter((c) => c.cmd.includes(` --worker ${kind} `));
