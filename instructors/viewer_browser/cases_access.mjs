// Who may talk to the viewer, in a real browser: a page of another port of
// 127.0.0.1 cannot start a render with the viewer's cookie, two viewers in
// one browser keep their own cookies, and a refused request says why in
// the page.
import http from 'node:http';
import {args, OUT, check, rawRequest, startViewer, stopViewer, withViewerPage, waitEvent, lastJob, renderEnd,
        SCENE} from './harness.mjs';
import path from 'node:path';

export const cases = {};

// Serves `html` at / on a free port of 127.0.0.1; resolves with {url, close}.
function servePage(html) {
  return new Promise((resolve) => {
    const server = http.createServer((req, res) => {
      res.writeHead(200, {'Content-Type': 'text/html; charset=utf-8'});
      res.end(html);
    });
    server.listen(0, '127.0.0.1', () => resolve({
      url: `http://127.0.0.1:${server.address().port}/`,
      // The browser keeps its idle connection open for a minute: close it
      // rather than wait for it.
      close: () => new Promise((r) => {
        server.close(r);
        server.closeAllConnections();
      }),
    }));
  });
}

// A page on another port tries what a browser lets any page do: a
// "no-cors" text/plain fetch, a form post (text/plain and urlencoded) and a
// JSON fetch (which needs the viewer's consent first), all with the
// viewer's cookie going along. None starts a render.
cases.cross_site_page = async () => {
  await withViewerPage(['-r', '32', '24', '-s', '1', SCENE()], async (page, v) => {
    const first = await renderEnd(page, await lastJob(page));
    check(first.state === 'done', 'the viewer\'s page renders (its cookie is set)', first.state);
    const target = `http://127.0.0.1:${v.port}/api/render`;
    const attacker = await servePage(`<!doctype html><body><iframe name="sink"></iframe><script>
      const results = [];
      const form = (enctype, name, value) => new Promise((done) => {
        const f = document.createElement('form');
        Object.assign(f, {method: 'POST', action: ${JSON.stringify(target)}, target: 'sink', enctype});
        const i = document.createElement('input');
        Object.assign(i, {name, value});
        f.appendChild(i);
        document.body.appendChild(f);
        document.querySelector('iframe').onload = done;
        f.submit();
      });
      (async () => {
        try {
          await fetch(${JSON.stringify(target)}, {method: 'POST', mode: 'no-cors', credentials: 'include',
                                                  headers: {'Content-Type': 'text/plain'}, body: '{"seed": 71}'});
          results.push('no-cors fetch sent');
        } catch (e) { results.push('no-cors fetch: ' + e); }
        await form('text/plain', '{"seed": 72, "x": "', '"}');
        results.push('text/plain form sent');
        await form('application/x-www-form-urlencoded', 'seed', '73');
        results.push('urlencoded form sent');
        try {
          await fetch(${JSON.stringify(target)}, {method: 'POST', credentials: 'include',
                                                  headers: {'Content-Type': 'application/json'}, body: '{"seed": 74}'});
          results.push('JSON fetch answered');
        } catch (e) { results.push('JSON fetch blocked'); }
        document.body.dataset.results = JSON.stringify(results);
      })();
    </script></body>`);
    try {
      const evil = await page.context().newPage();
      await evil.goto(attacker.url);
      const results = JSON.parse(await (await evil.waitForFunction(() => document.body.dataset.results)).jsonValue());
      check(results.length === 4, 'the other port\'s page made its four attempts', JSON.stringify(results));
      check(results[3] === 'JSON fetch blocked', 'its JSON fetch is blocked (the viewer gives no consent)', results[3]);
      await evil.screenshot({path: path.join(OUT, 'cross_site_page.png')});
      await evil.close();
    } finally {
      await attacker.close();
    }
    const own = await rawRequest(v, {method: 'POST', path: '/api/render', body: '{}',
                                     headers: {'X-Token': v.token, 'Content-Type': 'application/json'}});
    const job = JSON.parse(own.body).job;
    check(job === first.job + 1, `no render was started from the other port: the next job is ${first.job + 1}`, `job ${job}`);
  });
};

// Two viewers in one browser: the second page's cookie does not replace
// the first's, so the first tab keeps working; with its cookie gone, a
// refused request says in the page why and what to do.
cases.two_viewers = async () => {
  await withViewerPage(['-r', '32', '24', '-s', '1', SCENE()], async (page, v, errors) => {
    const first = await renderEnd(page, await lastJob(page));
    const other = await startViewer(args.viewer, ['-r', '32', '24', '-s', '1', SCENE()]);
    try {
      const tab2 = await page.context().newPage();
      await tab2.goto(other.url);
      await tab2.waitForFunction(() => document.body.dataset.ready === '1');
      const end2 = await renderEnd(tab2, await lastJob(tab2));
      check(end2.state === 'done', 'the second viewer\'s tab renders', end2.state);
      await page.bringToFront();
      await page.keyboard.press('r');
      const next = await waitEvent(page, `(e.type === 'render' && e.job > ${first.job}) || e.type === 'refused'`);
      check(next.type === 'render', 'the first tab still starts renders after the second viewer\'s page opened',
            JSON.stringify(next));
      if (next.type === 'render') {
        const end = await renderEnd(page, next.job);
        check(end.state === 'done' && !(await page.locator('#banner').isVisible()), 'and it finishes without a banner',
              end.state);
      }
      await page.screenshot({path: path.join(OUT, 'two_viewers_first_tab.png')});
      // Without its cookie (cleared, say), the first tab's requests are
      // refused, and the page says why and what to do.
      await page.context().clearCookies();
      await page.keyboard.press('r');
      const refused = await waitEvent(page, `e.type === 'refused'`);
      const text = await page.locator('#banner').textContent();
      check(refused.status === 403 && /does not carry this viewer's token/.test(text) &&
            text.includes(`open the URL the viewer printed when it started (http://127.0.0.1:${v.port}/?token=...)`),
            'a refused request shows the reason and what to do in the banner', `${refused.status}: ${text}`);
      await page.screenshot({path: path.join(OUT, 'refused_banner.png')});
      const refusedLog = (e) => /status of 403/.test(e);
      check(errors.filter((e) => !refusedLog(e)).length === 0, 'no script errors in the page', errors.join('; '));
    } finally {
      await stopViewer(other);
    }
  });
};
