// Browser test of the fairsurf editor against a running server (the Rust
// `fairsurf serve`, or tests/mock-server.mjs). Relies only on editor/API.md.
//
//   node editor/tests/editor.test.mjs http://127.0.0.1:PORT [example.json]
//
// Exit 0 when every step passes; otherwise 1 with the failing step named.
// CHROMIUM=/path/to/chrome overrides the browser (default /usr/bin/chromium).

import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const OUT = path.join(here, 'out');
const base = (process.argv[2] || '').replace(/\/+$/, '');
const wantedExample = process.argv[3] || null;
const STEP_TIMEOUT_MS = Number(process.env.STEP_TIMEOUT_MS || 60_000);

if (!/^https?:\/\//.test(base)) {
  console.error('usage: node editor/tests/editor.test.mjs http://127.0.0.1:PORT [example.json]');
  process.exit(2);
}

class Failure extends Error {}
function assert(cond, message) {
  if (!cond) throw new Failure(message);
}

let browser;
const pageErrors = [];
const consoleErrors = [];

async function finish(code) {
  await browser?.close().catch(() => {});
  process.exit(code);
}

/** Runs one named step with a time limit; prints "ok" or fails the test. */
async function step(name, fn) {
  const t0 = Date.now();
  let timer;
  try {
    const detail = await Promise.race([
      fn(),
      new Promise((_, reject) => {
        timer = setTimeout(() => reject(new Failure(`timed out after ${STEP_TIMEOUT_MS} ms`)), STEP_TIMEOUT_MS);
      }),
    ]);
    clearTimeout(timer);
    if (pageErrors.length) throw new Failure(`uncaught error in the page: ${pageErrors.join(' | ')}`);
    const text = detail && typeof detail === 'object' ? detail.detail : detail;
    console.log(`ok   ${name}${text ? ` — ${text}` : ''} (${Date.now() - t0} ms)`);
    return detail;
  } catch (err) {
    clearTimeout(timer);
    console.log(`FAIL ${name}: ${err instanceof Failure ? err.message : err.stack || err}`);
    if (consoleErrors.length) console.log(`     browser console errors:\n       ${consoleErrors.slice(-8).join('\n       ')}`);
    await finish(1);
  }
}

const sameJson = (a, b) => JSON.stringify(a) === JSON.stringify(b);

try {
  browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    args: [
      '--headless',
      '--no-sandbox',
      '--disable-gpu',
      '--disable-quic',
      '--no-first-run',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
      // WebGL without a GPU: software rendering through SwiftShader.
      '--use-angle=swiftshader',
      '--enable-unsafe-swiftshader',
    ],
  });
} catch (err) {
  console.log(`FAIL launch chromium: ${err.message}`);
  process.exit(1);
}

const context = await browser.newContext({ viewport: { width: 1280, height: 800 }, acceptDownloads: true });
const page = await context.newPage();
page.on('pageerror', (err) => pageErrors.push(err.message));
page.on('console', (msg) => {
  if (msg.type() === 'error') consoleErrors.push(msg.text());
});
/** The bodies of the solve requests the page sent, in order. */
const solveRequests = [];
page.on('request', (req) => {
  if (req.method() === 'POST' && new URL(req.url()).pathname.endsWith('/api/solve')) {
    try {
      solveRequests.push(JSON.parse(req.postData() || 'null'));
    } catch {
      solveRequests.push(null);
    }
  }
});

/**
 * The table's rows as text, without the ones that change on every solve
 * whatever the scene (timings, whether a factorization was reused).
 */
const energyTable = () =>
  page.evaluate(() =>
    [...document.querySelectorAll('[data-testid="energy-table"] tbody tr')]
      .map((tr) => tr.innerText)
      .filter((t) => !/\(ms\)|factorization/.test(t))
      .join('\n'),
  );

/** Waits in the page until no solve is pending or in flight and the frame is drawn. */
const idle = () => page.evaluate(() => window.fairsurf.idle());
const hooks = () =>
  page.evaluate(() => ({
    solveCount: window.fairsurf.solveCount,
    renderCount: window.fairsurf.renderCount,
    errorCount: window.fairsurf.errorCount,
  }));

// ------------------------------------------------------------------ steps

await step('open the page', async () => {
  const res = await page.goto(`${base}/`, { waitUntil: 'load' });
  assert(res && res.ok(), `GET / answered ${res?.status()}`);
  await page.waitForFunction(() => window.fairsurf && window.fairsurf.ready, null, { timeout: 20_000 });
  await page.evaluate(() => window.fairsurf.ready);
  assert(await page.locator('[data-testid="viewport-canvas"]').isVisible(), 'the viewport canvas is not visible');
  const webgl = await page.evaluate(() => !!window.fairsurf.viewer.renderer.getContext());
  assert(webgl, 'no WebGL context');
  const n = await page.locator('[data-testid="example-select"] option[value]:not([value=""])').count();
  assert(n > 0, 'the example list is empty');
  return `${n} examples listed`;
});

const chosen = await step('load an example with sliders and handles', async () => {
  const list = await page.evaluate(async () => (await (await fetch('/api/examples')).json()).examples);
  assert(Array.isArray(list) && list.length, 'GET /api/examples returned no examples');
  const candidates = wantedExample ? [wantedExample] : list.map((e) => e.file);
  for (const file of candidates) {
    const outcome = await page.evaluate((f) => window.fairsurf.loadExample(f), file);
    const r = await page.evaluate(() => {
      const resp = window.fairsurf.lastResponse;
      return resp && { sliders: resp.sliders?.length ?? 0, handles: resp.handles?.length ?? 0, kind: resp.kind };
    });
    if (outcome.ok && r && r.sliders > 0 && r.handles > 0) {
      const ui = await page.evaluate(() => ({
        select: document.querySelector('[data-testid="example-select"]').value,
        rows: document.querySelectorAll('[data-testid="energy-table"] tbody tr').length,
        sliders: document.querySelectorAll('[data-testid="slider"]').length,
        error: !document.querySelector('[data-testid="error"]').hidden,
        triangles: window.fairsurf.lastResponse.mesh.indices.length / 3,
      }));
      assert(ui.select === file, `the example select shows ${JSON.stringify(ui.select)}, not ${file}`);
      assert(ui.rows > 0, 'the energy table is empty');
      assert(ui.sliders === r.sliders, `${ui.sliders} slider inputs for ${r.sliders} sliders in the response`);
      assert(!ui.error, 'the error element is shown after a good solve');
      assert(ui.triangles > 0, 'the response mesh has no triangles');
      return { file, kind: r.kind, detail: `${file} (${r.kind}, ${r.sliders} sliders, ${r.handles} handles, ${ui.triangles} triangles)` };
    }
    if (wantedExample) {
      assert(false, `${file}: ${outcome.ok ? `${r?.sliders} sliders, ${r?.handles} handles` : `solve failed: ${outcome.error?.error}`}`);
    }
  }
  assert(false, 'no example has both sliders and handles');
});

await step('move a slider: the table changes and the surface re-renders', async () => {
  const count = await page.locator('[data-testid="slider"]').count();
  for (let k = 0; k < count; k++) {
    const slider = page.locator('[data-testid="slider"]').nth(k);
    const pointer = await slider.getAttribute('data-pointer');
    const before = {
      value: await page.evaluate((p) => window.fairsurf.getPointer(p), pointer),
      table: await energyTable(),
      ...(await hooks()),
    };
    // Click the track at 15% or 85%, away from the thumb: a real mouse event.
    const box = await slider.boundingBox();
    const position = Number(await slider.inputValue()) / Number(await slider.getAttribute('max'));
    const at = position > 0.5 ? 0.15 : 0.85;
    await page.mouse.click(box.x + box.width * at, box.y + box.height / 2);
    await idle();
    const after = {
      value: await page.evaluate((p) => window.fairsurf.getPointer(p), pointer),
      table: await energyTable(),
      ...(await hooks()),
    };
    assert(!sameJson(after.value, before.value), `slider ${pointer}: the scene value stayed ${JSON.stringify(before.value)}`);
    assert(after.solveCount > before.solveCount, `slider ${pointer}: no new solve (solveCount ${after.solveCount})`);
    assert(after.errorCount === before.errorCount, `slider ${pointer}: the solve failed: ${await page.locator('[data-testid="error"]').innerText()}`);
    assert(after.renderCount > before.renderCount, `slider ${pointer}: no new frame (renderCount ${after.renderCount})`);
    if (after.table !== before.table) {
      return `${pointer}: ${JSON.stringify(before.value)} → ${JSON.stringify(after.value)}, solves ${before.solveCount} → ${after.solveCount}, frames ${before.renderCount} → ${after.renderCount}`;
    }
  }
  assert(false, 'no slider changed the energy table');
});

await step('drag a control-point handle with the mouse', async () => {
  const { handles, rect } = await page.evaluate(() => {
    const r = document.querySelector('[data-testid="viewport-canvas"]').getBoundingClientRect();
    return {
      handles: window.fairsurf.lastResponse.handles.map((h, k) => ({ ...h, screen: window.fairsurf.handleScreenPosition(k) })),
      rect: { left: r.left, top: r.top, right: r.right, bottom: r.bottom },
    };
  });
  // The handle farthest (on screen) from every other one, well inside the
  // canvas and away from the overlays in its corners, so the mouse grabs it
  // and nothing else. A point handle (no `edit`: its position is its value,
  // editor/API.md), not a direction or an offset.
  const usable = handles
    .map((h, index) => ({ ...h, index }))
    .filter((h) => !h.edit)
    .filter((h) => h.screen && h.screen.inView)
    .filter((h) => h.screen.x > rect.left + 30 && h.screen.x < rect.right - 120 && h.screen.y > rect.top + 70 && h.screen.y < rect.bottom - 90);
  assert(usable.length > 0, `none of ${handles.length} handles is on screen`);
  for (const h of usable) {
    h.gap = Math.min(...handles.filter((o) => o !== handles[h.index] && o.screen).map((o) => Math.hypot(o.screen.x - h.screen.x, o.screen.y - h.screen.y)), Infinity);
  }
  usable.sort((a, b) => (a.kind === 'control_point') - (b.kind === 'control_point') || a.gap - b.gap);
  const h = usable[usable.length - 1]; // a control point if any, most isolated
  const before = {
    value: await page.evaluate((p) => window.fairsurf.getPointer(p), h.pointer),
    camera: await page.evaluate(() => window.fairsurf.viewer.camera.position.toArray()),
    ...(await hooks()),
  };
  const { x, y } = h.screen;
  const sentBefore = solveRequests.length;
  await page.mouse.move(x, y);
  await page.mouse.down();
  // Slow enough that solves go out while the button is down.
  for (let k = 1; k <= 4; k++) {
    await page.mouse.move(x + 12 * k, y - 10 * k, { steps: 3 });
    await page.waitForTimeout(150);
  }
  const duringDrag = solveRequests.slice(sentBefore);
  await page.mouse.up();
  await idle();
  const sent = solveRequests.slice(sentBefore);
  const after = {
    value: await page.evaluate((p) => window.fairsurf.getPointer(p), h.pointer),
    camera: await page.evaluate(() => window.fairsurf.viewer.camera.position.toArray()),
    response: await page.evaluate((p) => window.fairsurf.lastResponse.handles.find((o) => o.pointer === p), h.pointer),
    ...(await hooks()),
  };
  assert(Array.isArray(after.value) && after.value.length === 3 && after.value.every(Number.isFinite), `the scene value at ${h.pointer} is ${JSON.stringify(after.value)}, not [x, y, z]`);
  assert(!sameJson(after.value, before.value), `the scene value at ${h.pointer} did not change (${JSON.stringify(before.value)}): the drag did not grab the handle`);
  assert(after.solveCount > before.solveCount, 'no new solve after the drag');
  assert(after.errorCount === before.errorCount, `the solve after the drag failed: ${await page.locator('[data-testid="error"]').innerText()}`);
  assert(sameJson(after.camera, before.camera), 'the camera moved: the drag also orbited the view');
  // Quick answers while dragging, one full answer after letting go.
  assert(duringDrag.length > 0 && duringDrag.every((b) => b?.quick === true), `requests while dragging: ${JSON.stringify(duringDrag.map((b) => b?.quick))}, expected quick: true`);
  assert(sent.length > duringDrag.length && sent[sent.length - 1]?.quick === false, `the last request after letting go: ${JSON.stringify(sent.map((b) => b?.quick))}, expected quick: false`);
  const shown = await page.evaluate(() => ({ quick: window.fairsurf.lastResponse.quick, stale: document.querySelectorAll('[data-testid="energy-table"] tr.stale').length }));
  assert(shown.quick !== true && shown.stale === 0, `after letting go the page shows a quick answer (${JSON.stringify(shown)})`);
  assert(after.response, `the new response has no handle ${h.pointer}`);
  const off = Math.max(...after.response.position.map((c, k) => Math.abs(c - after.value[k])));
  const size = Math.max(1e-9, ...after.value.map(Math.abs));
  assert(off <= 1e-6 * Math.max(1, size), `the handle ${h.pointer} is drawn at ${JSON.stringify(after.response.position)}, the scene says ${JSON.stringify(after.value)}`);
  return `${h.label || h.pointer}: ${JSON.stringify(before.value)} → ${JSON.stringify(after.value)}, solves ${before.solveCount} → ${after.solveCount} (${duringDrag.length} quick while dragging)`;
});

await step('turn a direction handle: the direction turns, its length stays', async () => {
  const list = await page.evaluate(async () => (await (await fetch('/api/examples')).json()).examples);
  // Directors are the likeliest to have one; any example will do.
  const files = list.map((e) => e.file).sort((a, b) => /director/.test(b) - /director/.test(a));
  let found = null;
  for (const file of files) {
    const outcome = await page.evaluate((f) => window.fairsurf.loadExample(f), file);
    if (!outcome.ok) continue;
    const { handles, rect } = await page.evaluate(() => {
      const r = document.querySelector('[data-testid="viewport-canvas"]').getBoundingClientRect();
      return {
        handles: window.fairsurf.lastResponse.handles.map((h, k) => ({ ...h, index: k, screen: window.fairsurf.handleScreenPosition(k) })),
        rect: { left: r.left, top: r.top, right: r.right, bottom: r.bottom },
      };
    });
    const inside = (h) => h.screen && h.screen.inView && h.screen.x > rect.left + 80 && h.screen.x < rect.right - 160 && h.screen.y > rect.top + 110 && h.screen.y < rect.bottom - 110;
    const gap = (h) => Math.min(...handles.filter((o) => o !== h && o.screen).map((o) => Math.hypot(o.screen.x - h.screen.x, o.screen.y - h.screen.y)), Infinity);
    const candidates = handles.filter((h) => h.edit?.type === 'direction' && inside(h) && gap(h) > 12);
    if (candidates.length) {
      found = { file, h: candidates.sort((a, b) => gap(b) - gap(a))[0] };
      break;
    }
  }
  assert(found, 'no example has a direction handle on screen');
  const { file, h } = found;
  const norm = (v) => Math.hypot(...v);
  const before = {
    value: await page.evaluate((p) => window.fairsurf.getPointer(p), h.pointer),
    table: await energyTable(),
    ...(await hooks()),
  };
  const { x, y } = h.screen;
  await page.mouse.move(x, y);
  await page.mouse.down();
  for (let k = 1; k <= 4; k++) {
    await page.mouse.move(x + 10 * k, y - 6 * k, { steps: 3 });
    await page.waitForTimeout(100);
  }
  // While held, the handle stays on its sphere about the anchor.
  const held = await page.evaluate((k) => window.fairsurf.viewer.handleMeshes[k].position.toArray(), h.index);
  const radius = norm(held.map((c, i) => c - h.edit.anchor[i]));
  assert(Math.abs(radius - h.edit.length) <= 1e-6 * h.edit.length, `while dragged the handle is ${radius} from its anchor, not ${h.edit.length}`);
  await page.mouse.up();
  await idle();
  const after = {
    value: await page.evaluate((p) => window.fairsurf.getPointer(p), h.pointer),
    table: await energyTable(),
    offset: h.edit.offset ? await page.evaluate((p) => window.fairsurf.getPointer(p), h.edit.offset) : null,
    response: await page.evaluate((p) => window.fairsurf.lastResponse.handles.find((o) => o.pointer === p), h.pointer),
    ...(await hooks()),
  };
  assert(after.errorCount === before.errorCount, `the solve after turning failed: ${await page.locator('[data-testid="error"]').innerText()}`);
  assert(!sameJson(after.value, before.value), `${h.pointer} stayed ${JSON.stringify(before.value)}: the drag did not grab the handle`);
  const turned = Math.acos(Math.min(1, after.value.reduce((a, c, i) => a + c * before.value[i], 0) / (norm(after.value) * norm(before.value))));
  assert(turned > 0.01, `${h.pointer} turned by only ${turned} rad`);
  assert(Math.abs(norm(after.value) - norm(before.value)) <= 1e-5 * norm(before.value), `the direction's length changed: ${norm(before.value)} → ${norm(after.value)}`);
  if (h.edit.offset) {
    const through = after.value.reduce((a, c, i) => a + c * h.edit.anchor[i], 0);
    assert(Math.abs(after.offset - through) <= 1e-5 * Math.max(1, Math.abs(through)), `the plane no longer passes through its anchor: offset ${after.offset}, n·anchor ${through}`);
  }
  assert(after.table !== before.table, 'turning the direction did not change the table');
  assert(after.response?.edit?.type === 'direction', `the new response has no direction handle ${h.pointer}`);
  const e = after.response.edit;
  const want = e.anchor.map((a, i) => a + (e.length * after.value[i]) / norm(after.value));
  const off = Math.max(...want.map((c, i) => Math.abs(c - after.response.position[i])));
  assert(off <= 1e-6 * Math.max(1, e.length), `the handle is drawn at ${JSON.stringify(after.response.position)}, anchor + length·direction is ${JSON.stringify(want)}`);
  return `${file}, ${h.label || h.pointer}: ${JSON.stringify(before.value)} → ${JSON.stringify(after.value)} (${turned.toFixed(3)} rad), solves ${before.solveCount} → ${after.solveCount}`;
});

await step('load a bad scene: the server\'s error is shown, the surface stays', async () => {
  const bad = await page.evaluate(() => {
    const s = structuredClone(window.fairsurf.scene);
    s.surface.degree = 'five';
    return s;
  });
  const server = await page.evaluate(async (scene) => {
    const res = await fetch('/api/solve', { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify({ scene }) });
    return { status: res.status, body: await res.json().catch(() => null) };
  }, bad);
  assert(server.status >= 400 && server.status < 500, `POST /api/solve with surface.degree = "five" answered ${server.status}, expected 4xx`);
  assert(server.body && typeof server.body.error === 'string', `the error body is ${JSON.stringify(server.body)}, expected {"error": "...", "path": ...}`);
  const before = await hooks();
  const outcome = await page.evaluate((scene) => window.fairsurf.loadScene(scene), bad);
  assert(outcome.ok === false, 'loadScene reported success for a bad scene');
  const error = page.locator('[data-testid="error"]');
  assert(await error.isVisible(), 'the error element is not visible');
  const text = await error.innerText();
  assert(text.includes(server.body.error), `the error element says ${JSON.stringify(text)}, the server said ${JSON.stringify(server.body.error)}`);
  assert(text.includes(server.body.path || 'surface.degree'), `the error ${JSON.stringify(text)} does not name the JSON path ${server.body.path || 'surface.degree'}`);
  assert(await error.getAttribute('role') === 'alert', 'the error element has no role="alert"');
  const drawn = await page.evaluate(() => window.fairsurf.viewer.groups.surface.children.length);
  const after = await hooks();
  assert(drawn > 0 && after.solveCount === before.solveCount, 'the last good surface is no longer drawn');
  return `${server.status}: ${server.body.error}`;
});

await step('load a scene file through the file input: the error clears', async () => {
  const file = chosen.file;
  const scene = await page.evaluate(async (f) => (await fetch(`/api/examples/${encodeURIComponent(f)}`)).json(), file);
  const before = await hooks();
  await page.locator('[data-testid="file-input"]').setInputFiles({ name: file, mimeType: 'application/json', buffer: Buffer.from(JSON.stringify(scene)) });
  await page.waitForFunction((n) => window.fairsurf.solveCount > n, before.solveCount, { timeout: STEP_TIMEOUT_MS });
  await idle();
  assert(await page.locator('[data-testid="error"]').isHidden(), 'the error element is still shown after a good scene');
  return `${file} solved again`;
});

await step('export OBJ and save the scene (downloads)', async () => {
  const [obj] = await Promise.all([page.waitForEvent('download'), page.locator('[data-testid="export-obj"]').click()]);
  const objPath = await obj.path();
  const objText = fs.readFileSync(objPath, 'utf8');
  assert(/\.obj$/i.test(obj.suggestedFilename()), `the OBJ download is named ${obj.suggestedFilename()}`);
  assert(/^v /m.test(objText) && /^f /m.test(objText), 'the OBJ download has no vertices or faces');
  const [saved] = await Promise.all([page.waitForEvent('download'), page.locator('[data-testid="save-scene"]').click()]);
  const scene = JSON.parse(fs.readFileSync(await saved.path(), 'utf8'));
  const current = await page.evaluate(() => window.fairsurf.scene);
  assert(sameJson(scene, current), 'the saved scene is not the scene being edited');
  return `${obj.suggestedFilename()} (${objText.length} bytes), ${saved.suggestedFilename()}`;
});

if (chosen.kind === 'tensor') {
  await step('compare surfaces', async () => {
    await page.locator('[data-testid="compare-button"]').click();
    const table = page.locator('[data-testid="compare-table"]');
    const error = page.locator('[data-testid="error"]');
    await Promise.race([table.waitFor({ state: 'visible' }), error.waitFor({ state: 'visible' })]);
    assert(await error.isHidden(), `compare failed: ${await error.innerText().catch(() => '')}`);
    const rows = await table.locator('tbody tr').count();
    assert(rows > 0, 'the compare table has no rows');
    return `${rows} rows`;
  });
}

await step('screenshot is not blank', async () => {
  fs.mkdirSync(OUT, { recursive: true });
  const file = path.join(OUT, 'editor.png');
  const png = await page.screenshot({ path: file });
  const rect = await page.evaluate(() => {
    const r = document.querySelector('[data-testid="viewport-canvas"]').getBoundingClientRect();
    return { x: r.left, y: r.top, w: r.width, h: r.height };
  });
  // Decode the PNG in the page (no image library here) and count the
  // distinct colours inside the viewport: a shaded, coloured surface has
  // thousands, an empty or failed canvas a handful.
  const colours = await page.evaluate(
    async ({ dataUrl, rect }) => {
      const img = new Image();
      img.src = dataUrl;
      await img.decode();
      const c = document.createElement('canvas');
      c.width = Math.round(rect.w);
      c.height = Math.round(rect.h);
      const g = c.getContext('2d');
      const sx = img.width / window.innerWidth;
      g.drawImage(img, rect.x * sx, rect.y * sx, rect.w * sx, rect.h * sx, 0, 0, c.width, c.height);
      const data = g.getImageData(0, 0, c.width, c.height).data;
      const seen = new Set();
      for (let k = 0; k < data.length; k += 4) seen.add((data[k] << 16) | (data[k + 1] << 8) | data[k + 2]);
      return seen.size;
    },
    { dataUrl: `data:image/png;base64,${png.toString('base64')}`, rect },
  );
  assert(colours >= 200, `the viewport has only ${colours} distinct colours: nothing drawn?`);
  return `${path.relative(process.cwd(), file)}, ${colours} distinct colours in the viewport`;
});

console.log('PASS editor test');
await finish(0);
