// The fairsurf editor page: holds the scene JSON the user edits, sends it to
// the server to be solved, and shows the answer (see editor/API.md).
//
// Solving is live: every edit (slider, handle drag, method) marks the scene
// dirty and schedules a solve after a short debounce. At most one request is
// in flight; when it returns and the scene changed meanwhile, the latest
// state is sent next. Each request carries a sequence number and the
// "epoch" of the scene it belongs to (bumped when a new scene is loaded), so
// a response for a scene no longer loaded, or older than one already shown,
// is dropped.
//
// While a handle or a slider is being dragged the requests ask for a quick
// answer ("quick": true: the server skips the area and the other measures,
// and re-solves with the factorization it kept); letting go sends one full
// solve. Rows of the table that a quick answer lacks keep their last full
// value, greyed.

import { Viewer } from './viewer.js';
import {
  getPointer,
  setPointer,
  formatNumber,
  formatShort,
  formatSeconds,
  downloadBlob,
  dispositionFilename,
  baseName,
  decodeMesh,
  roundTo,
} from './util.js';

const DEBOUNCE_MS = 30;
const SLIDER_STEPS = 1000; // resolution of a range input

const $ = (id) => document.getElementById(id);

const state = {
  scene: null, // the scene JSON being edited
  fileName: 'scene.json', // where it came from: names the downloads
  epoch: 0, // bumped by every scene load
  loadToken: 0, // the latest load request (example fetches can race)
  seq: 0, // last solve request sent
  lastApplied: 0, // seq of the response on screen
  responseEpoch: -1, // epoch of the response on screen
  inFlight: false,
  dirty: false, // the scene changed since the last request was sent
  timer: null, // pending debounce
  needsFrame: true, // frame the camera on the next good response
  lastResponse: null,
  lastError: null, // { error, path } of the latest failure, null after a success
  outcome: null, // { epoch, ok, error } of the latest response
  solveCount: 0,
  errorCount: 0,
  sliderKey: null, // identifies the slider set on screen
  activeSlider: null, // pointer of the slider under the mouse
  pendingSliders: null, // a slider set to build once the active one is released
  idleWaiters: [],
  compareEpoch: -1,
  compareVersion: -1,
  version: 0, // bumped by every edit of the scene
  handleDrag: false, // a handle is being dragged
  dragHandle: null, // the dragged handle's descriptor when the drag began
  dragLength: null, // |value| of a dragged direction when the drag began
  needFull: false, // a quick answer was asked for since the last full one
  fullTable: null, // the table of the last full answer for this scene
};

let viewer;
try {
  viewer = new Viewer($('viewport'), {
    onHandleDrag: (index, position) => {
      startDrag(index);
      moveHandle(state.dragHandle, position);
    },
    onHandleDragEnd: () => {
      state.handleDrag = false;
      state.dragHandle = null;
      state.dragLength = null;
      finishDrag();
    },
    onRender: () => checkIdle(),
    describeHandle: (index) => {
      const h = viewer.handles[index];
      if (!h?.edit || !state.scene) return null;
      const v = getPointer(state.scene, h.pointer);
      const f = (x) => String(Number(x.toPrecision(5)));
      // The label names the field ("tilt: direction", "shelf: offset").
      if (isVec3(v)) return `${h.label || h.pointer}  (${v.map(f).join(', ')})`;
      return typeof v === 'number' ? `${h.label || h.pointer}  ${f(v)}` : null;
    },
    constrainHandle: (index, position) => {
      startDrag(index);
      const h = state.dragHandle;
      if (!h?.edit) return null;
      const edits = handleEdits(h, position);
      // Too close to the anchor to say a direction: it stays where it is.
      return handlePosition(h, edits.length ? edits[0][1] : getPointer(state.scene, h.pointer));
    },
  });
} catch (err) {
  // Typically no WebGL: say so on the page rather than only in the console.
  showError({ error: `The 3D view cannot start: ${err.message}. The editor needs WebGL.`, path: null });
  throw err;
}

// ------------------------------------------------------------------ HTTP

/** Reads an error body `{error, path}`; anything else becomes a readable message. */
async function readError(res) {
  const text = await res.text().catch(() => '');
  try {
    const body = JSON.parse(text);
    if (body && typeof body.error === 'string') return { error: body.error, path: body.path ?? null, status: res.status };
  } catch {
    /* not JSON */
  }
  const detail = text.trim().slice(0, 300);
  return { error: `${res.status} ${res.statusText || 'error'}${detail ? `: ${detail}` : ''}`, path: null, status: res.status };
}

/** A failed fetch (TypeError) or an unreadable answer, as an error to show. */
function networkError(err) {
  if (err instanceof TypeError) {
    return { error: `Cannot reach the fairsurf server (${err.message}). Is \`fairsurf serve\` still running?`, path: null };
  }
  return { error: `Unexpected answer from the server: ${err.message || err}`, path: null };
}

async function postJson(url, body) {
  return fetch(url, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify(body),
  });
}

// ---------------------------------------------------------------- solving

/** Marks the scene edited and solves it after `delay` ms (debounced). */
function scheduleSolve(delay = DEBOUNCE_MS) {
  state.dirty = true;
  clearTimeout(state.timer);
  state.timer = setTimeout(() => {
    state.timer = null;
    pump();
  }, delay);
  updateBusy();
}

/** Skips the rest of a pending debounce (the user let go of a handle). */
function flushSolve() {
  if (state.timer === null) return;
  clearTimeout(state.timer);
  state.timer = null;
  pump();
}

/** Whether the user is dragging a handle or a slider. */
function dragging() {
  return state.handleDrag || state.activeSlider !== null;
}

/** The user let go: solve at once, fully if a quick answer is on screen. */
function finishDrag() {
  if (state.needFull && state.scene) state.dirty = true;
  if (state.timer !== null) flushSolve();
  else pump();
}

/** Sends the latest scene unless a request is already in flight. */
async function pump() {
  if (state.inFlight || !state.dirty || !state.scene) {
    checkIdle();
    return;
  }
  state.dirty = false;
  const seq = ++state.seq;
  const epoch = state.epoch;
  state.inFlight = true;
  updateBusy();
  const t0 = performance.now();
  let res;
  let answer;
  try {
    // postJson serializes the scene before its first await: edits made
    // while the request is out go into the next one.
    const quick = dragging();
    state.needFull = quick;
    res = await postJson('api/solve', { scene: state.scene, quick, mesh_encoding: 'base64' });
    answer = res.ok ? await res.json() : await readError(res);
    if (res.ok) answer.mesh = decodeMesh(answer.mesh);
  } catch (err) {
    res = null;
    answer = networkError(err);
  }
  state.inFlight = false;
  // Drop an answer for a scene no longer loaded or older than the one shown.
  if (epoch === state.epoch && seq > state.lastApplied) {
    if (res?.ok) {
      try {
        applyResponse(answer, seq, epoch, performance.now() - t0);
      } catch (err) {
        console.error(err);
        applyError({ error: `Cannot show the server's answer: ${err.message}`, path: null }, epoch);
      }
    } else {
      applyError(answer, epoch);
    }
  }
  // An edit arrived while this request was out and its debounce already
  // fired: send it now.
  if (state.dirty && state.timer === null) pump();
  updateBusy();
  checkIdle();
}

function applyResponse(response, seq, epoch, roundTripMs) {
  const frame = state.needsFrame;
  state.lastApplied = seq;
  state.responseEpoch = epoch;
  state.lastResponse = response;
  state.lastError = null;
  state.outcome = { epoch, ok: true, error: null };
  state.needsFrame = false;
  state.solveCount++;
  clearError();
  viewer.handlesLocked = false;
  viewer.update(withSceneHandles(response), { frame });
  renderKind(response.kind);
  renderTable(tableRows(response.table || [], response.quick === true, epoch));
  renderLegend(response.mesh?.legend);
  renderMethods(response.methods ?? null);
  renderSliders(response.sliders || []);
  $('save-result').disabled = !response.result;
  $('compare').disabled = response.kind !== 'tensor';
  $('compare').title = response.kind === 'tensor'
    ? 'Compare this boundary\'s harmonic, biharmonic, mask and energy-minimizing surfaces'
    : 'Comparison is for tensor-product scenes';
  const server = formatSeconds(response.seconds);
  $('solve-time').textContent = server ? `solved in ${server}` : '';
  $('solve-time').title = `round trip ${roundTripMs.toFixed(0)} ms`;
  setStatus(`Solve #${state.solveCount}: ${server || '?'} on the server, ${roundTripMs.toFixed(0)} ms round trip.`);
  markCompareStale();
}

/**
 * The response with each handle placed at its value in the scene being
 * edited: after a drag, an answer for an intermediate position must not pull
 * the handle back. (They differ only while newer edits are on their way.)
 */
function withSceneHandles(response) {
  if (!Array.isArray(response.handles)) return response;
  const handles = response.handles.map((h) => {
    // The handle being dragged keeps the anchor it started with (unless
    // the handles changed under the drag, which then ends).
    const dragged = viewer.drag && response.handles[viewer.drag.index]?.pointer === h.pointer;
    const held = dragged && state.dragHandle?.pointer === h.pointer && h.edit ? { ...h, edit: state.dragHandle.edit } : h;
    const position = handlePosition(held, getPointer(state.scene, h.pointer));
    return position ? { ...held, position } : held;
  });
  return { ...response, handles };
}

/**
 * Remembers the handle `index` as a drag of it begins (or when the handle
 * under the drag is another one): its descriptor, so a direction turns
 * about the same anchor however many answers arrive meanwhile, and a
 * direction's length, so rounding cannot make it drift.
 */
function startDrag(index) {
  const h = viewer.handles[index] || null;
  if (state.handleDrag && state.dragHandle && state.dragHandle.pointer === h?.pointer) return;
  state.handleDrag = true;
  state.dragHandle = h;
  const v = h ? getPointer(state.scene, h.pointer) : null;
  state.dragLength = isVec3(v) ? Math.hypot(...v) || 1 : 1;
}

const isVec3 = (v) => Array.isArray(v) && v.length === 3 && v.every((c) => typeof c === 'number' && Number.isFinite(c));
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
/** A power of ten about 1e-6 of `size`: coordinates are rounded to it. */
const quantumOf = (size) => Math.pow(10, Math.floor(Math.log10(size * 1e-6)));

/**
 * Where the handle `h` is drawn when the scene's value at its pointer is
 * `value` (API.md, `handles[].edit`), or null if the value does not fit.
 */
function handlePosition(h, value) {
  const e = h.edit;
  if (!e) return isVec3(value) ? value : null;
  if (e.type === 'direction' && isVec3(value) && isVec3(e.anchor)) {
    const n = Math.hypot(...value);
    return n > 0 ? e.anchor.map((a, c) => a + (e.length * value[c]) / n) : null;
  }
  if (e.type === 'offset' && typeof value === 'number' && isVec3(e.anchor) && isVec3(e.normal)) {
    const nn = dot(e.normal, e.normal);
    if (!(nn > 0)) return null;
    const t = (value - dot(e.normal, e.anchor)) / nn;
    return e.anchor.map((a, c) => a + t * e.normal[c]);
  }
  return null;
}

/**
 * The scene edits, [[pointer, value], …], that put the handle `h` at
 * `position`: the point itself; for a direction the unit vector from its
 * anchor times the direction's length as it was (and a plane's offset so
 * that the plane still passes through the anchor); for an offset the
 * plane's through the position.
 */
function handleEdits(h, position) {
  const e = h.edit;
  const quantum = quantumOf(viewer.scale);
  if (!e) return [[h.pointer, position.map((v) => roundTo(v, quantum))]];
  if (e.type === 'direction' && isVec3(e.anchor)) {
    const v = position.map((p, c) => p - e.anchor[c]);
    const len = Math.hypot(...v);
    if (!(len > 1e-6 * e.length)) return [];
    const old = getPointer(state.scene, h.pointer);
    const keep = state.dragLength ?? ((isVec3(old) && Math.hypot(...old)) || 1);
    const d = v.map((x) => roundTo((keep * x) / len, quantumOf(keep)));
    const edits = [[h.pointer, d]];
    if (typeof e.offset === 'string') edits.push([e.offset, roundTo(dot(d, e.anchor), quantumOf(keep * viewer.scale))]);
    return edits;
  }
  if (e.type === 'offset' && isVec3(e.normal)) {
    return [[h.pointer, roundTo(dot(e.normal, position), quantumOf(Math.hypot(...e.normal) * viewer.scale))]];
  }
  return [];
}

function applyError(err, epoch) {
  state.lastError = err;
  state.outcome = { epoch, ok: false, error: err };
  state.errorCount++;
  showError(err);
  setStatus('The last solve failed; the last good surface stays drawn.');
}

function isIdle() {
  return !state.inFlight && !state.dirty && state.timer === null && !viewer.renderPending;
}

function checkIdle() {
  if (!isIdle()) return;
  const waiters = state.idleWaiters.splice(0);
  for (const resolve of waiters) resolve();
}

/** Resolves when no solve is pending or in flight and the last frame is drawn. */
function idle() {
  return new Promise((resolve) => {
    state.idleWaiters.push(resolve);
    checkIdle();
  });
}

function updateBusy() {
  $('busy').hidden = !(state.inFlight || state.dirty);
}

// ---------------------------------------------------------------- editing

/** Whether the controls on screen (sliders, handles) belong to the loaded scene. */
function controlsCurrent() {
  return state.scene !== null && state.responseEpoch === state.epoch;
}

function edit(pointer, value, delay = DEBOUNCE_MS) {
  editAll([[pointer, value]], delay);
}

/** Sets several scene values as one edit. */
function editAll(edits, delay = DEBOUNCE_MS) {
  if (edits.length === 0) return;
  for (const [pointer, value] of edits) setPointer(state.scene, pointer, value);
  state.version++;
  markCompareStale();
  scheduleSolve(delay);
}

function moveHandle(handle, position) {
  if (!handle || !controlsCurrent()) return;
  // Rounded to ~1e-6 of the scene size so a saved scene stays readable.
  editAll(handleEdits(handle, position));
}

/** Loads a scene object (a deep copy is edited), solves it, frames the camera. */
async function loadScene(obj, fileName = 'scene.json') {
  state.loadToken++;
  if (obj === null || typeof obj !== 'object' || Array.isArray(obj)) {
    const err = { error: 'A scene must be a JSON object.', path: null };
    applyError(err, state.epoch);
    return { ok: false, error: err };
  }
  state.scene = structuredClone(obj);
  state.fileName = fileName;
  state.epoch++;
  state.version++;
  state.needsFrame = true;
  state.outcome = null;
  const epoch = state.epoch;
  renderSceneInfo();
  // Sliders, method and handles refer to the previous scene until the
  // first solve of this one (the previous surface stays drawn meanwhile).
  renderSliders([]);
  renderMethods(null);
  viewer.handlesLocked = true;
  clearCompare();
  scheduleSolve(0);
  await idle();
  const outcome = state.outcome && state.outcome.epoch === epoch ? state.outcome : { ok: false, error: null, superseded: true };
  return { ok: outcome.ok, error: outcome.error, superseded: !!outcome.superseded };
}

/** Fetches a bundled example and loads it. */
async function loadExample(file) {
  const token = ++state.loadToken;
  const select = $('examples');
  if ([...select.options].some((o) => o.value === file)) select.value = file;
  let res;
  try {
    res = await fetch(`api/examples/${encodeURIComponent(file)}`);
  } catch (err) {
    const e = networkError(err);
    showError(e);
    return { ok: false, error: e };
  }
  if (!res.ok) {
    const e = await readError(res);
    showError(e);
    return { ok: false, error: e };
  }
  const scene = await res.json();
  if (token !== state.loadToken) return { ok: false, error: null, superseded: true }; // another load won
  history.replaceState(null, '', `#${encodeURIComponent(file)}`);
  return loadScene(scene, file);
}

async function loadFile(file) {
  const token = ++state.loadToken;
  let scene;
  try {
    scene = JSON.parse(await file.text());
  } catch (err) {
    showError({ error: `${file.name} is not JSON: ${err.message}`, path: null });
    return;
  }
  if (token !== state.loadToken) return;
  $('examples').value = '';
  history.replaceState(null, '', location.pathname);
  await loadScene(scene, file.name);
}

// ------------------------------------------------------------- rendering UI

function showError({ error, path }) {
  $('error-message').textContent = error;
  // The message normally names the path already; say it only if not.
  const extra = path && !error.includes(path) ? `at ${path}` : '';
  $('error-path').textContent = extra;
  $('error-path').hidden = !extra;
  $('error').hidden = false;
}

function clearError() {
  $('error').hidden = true;
  $('error-message').textContent = '';
  $('error-path').textContent = '';
}

function setStatus(text) {
  $('status').textContent = text;
}

function renderSceneInfo() {
  const s = state.scene || {};
  $('scene-title').textContent = typeof s.name === 'string' && s.name ? s.name : baseName(state.fileName);
  $('scene-description').textContent = typeof s.description === 'string' ? s.description : '';
}

function renderKind(kind) {
  const badge = $('kind');
  badge.hidden = !kind;
  badge.textContent = kind === 'bspline' ? 'B-spline' : String(kind || '');
}

/**
 * The rows to show: a full answer's as they are; a quick answer's in the
 * order of the last full table of this scene, with the rows it lacks kept
 * from there and marked stale.
 */
function tableRows(rows, quick, epoch) {
  if (!quick || !state.fullTable || state.fullTable.epoch !== epoch) {
    if (!quick) state.fullTable = { epoch, rows };
    return rows;
  }
  const fresh = new Map(rows.map((r) => [String(r.label), r]));
  const out = state.fullTable.rows.map((r) => fresh.get(String(r.label)) ?? { ...r, stale: true });
  const known = new Set(state.fullTable.rows.map((r) => String(r.label)));
  return out.concat(rows.filter((r) => !known.has(String(r.label))));
}

function renderTable(rows) {
  const tbody = $('table').tBodies[0];
  // Rows are updated in place when the labels are unchanged, so the table
  // does not flicker during live solves.
  const same = tbody.rows.length === rows.length && rows.every((r, k) => tbody.rows[k].dataset.label === String(r.label));
  if (!same) {
    tbody.replaceChildren(
      ...rows.map((r) => {
        const tr = document.createElement('tr');
        tr.dataset.label = String(r.label);
        const th = document.createElement('th');
        th.scope = 'row';
        th.textContent = r.label;
        tr.append(th, document.createElement('td'));
        return tr;
      }),
    );
  }
  rows.forEach((r, k) => {
    const td = tbody.rows[k].cells[1];
    td.textContent = formatNumber(r.value);
    td.title = typeof r.value === 'number' ? String(r.value) : '';
    tbody.rows[k].classList.toggle('stale', r.stale === true);
    if (r.stale) td.title = 'from the last full solve: updated when you let go';
  });
}

function renderLegend(legend) {
  const box = $('legend');
  if (!legend || !Array.isArray(legend.stops) || legend.stops.length === 0 || !viewer.visibility.surface) {
    box.hidden = true;
    return;
  }
  $('legend-name').textContent = legend.name || '';
  const stops = legend.stops.map(([t, color]) => `${color} ${(Number(t) * 100).toFixed(1)}%`).join(', ');
  $('legend-bar').style.background = `linear-gradient(to right, ${stops})`;
  $('legend-min').textContent = formatShort(legend.min);
  $('legend-max').textContent = formatShort(legend.max);
  box.hidden = false;
}

function renderMethods(methods) {
  const section = $('method-section');
  const select = $('method');
  if (!methods || !Array.isArray(methods.options)) {
    section.hidden = true;
    select.dataset.pointer = '';
    return;
  }
  section.hidden = false;
  select.dataset.pointer = methods.pointer;
  const key = methods.options.join('|');
  if (select.dataset.key !== key) {
    select.replaceChildren(...methods.options.map((o) => new Option(o.replace(/_/g, ' '), o)));
    select.dataset.key = key;
  }
  if (document.activeElement !== select) select.value = methods.value;
}

// Sliders map a range input's 0..SLIDER_STEPS to [min, max], linearly or
// logarithmically, and round the value to something a person would type.

function sliderPosition(s, v) {
  let t;
  if (s.scale === 'log') {
    if (!(v > 0)) return 0;
    t = (Math.log10(v) - Math.log10(s.min)) / (Math.log10(s.max) - Math.log10(s.min));
  } else {
    t = (v - s.min) / (s.max - s.min);
  }
  if (!Number.isFinite(t)) t = 0;
  return Math.round(Math.min(1, Math.max(0, t)) * SLIDER_STEPS);
}

function sliderValue(s, position) {
  const t = position / SLIDER_STEPS;
  if (s.scale === 'log') {
    const v = Math.pow(10, Math.log10(s.min) + t * (Math.log10(s.max) - Math.log10(s.min)));
    return Number(v.toPrecision(3));
  }
  const v = s.min + t * (s.max - s.min);
  const quantum = Math.pow(10, Math.floor(Math.log10((s.max - s.min) / SLIDER_STEPS)));
  return roundTo(v, quantum);
}

/** The value a slider shows: the scene's (the user's latest), else the server's default. */
function sliderCurrent(s) {
  const v = state.scene ? getPointer(state.scene, s.pointer) : undefined;
  return typeof v === 'number' ? v : s.value;
}

function renderSliders(sliders) {
  const key = JSON.stringify(sliders.map((s) => [s.pointer, s.min, s.max, s.scale, s.label]));
  const container = $('sliders');
  $('no-sliders').hidden = sliders.length > 0 || state.responseEpoch !== state.epoch;
  if (key === state.sliderKey) {
    // Same sliders: refresh the values, except the one being dragged.
    sliders.forEach((s, k) => {
      if (s.pointer === state.activeSlider) return;
      const row = container.children[k];
      row.slider = s;
      setSliderRow(row, sliderCurrent(s));
    });
    return;
  }
  if (state.activeSlider) {
    state.pendingSliders = sliders; // rebuilt when the drag ends
    return;
  }
  state.sliderKey = key;
  container.replaceChildren(...sliders.map((s, k) => sliderRow(s, k)));
}

function setSliderRow(row, value) {
  row.range.value = String(sliderPosition(row.slider, value));
  if (document.activeElement !== row.number) row.number.value = typeof value === 'number' ? formatShort(value) : '';
}

function sliderRow(s, k) {
  const row = document.createElement('div');
  row.className = 'slider-row';
  row.dataset.pointer = s.pointer;
  row.slider = s;
  const id = `slider-${k}`;
  const label = document.createElement('label');
  label.htmlFor = id;
  label.textContent = s.label;
  label.title = s.pointer + (s.scale === 'log' ? ' (log scale)' : '');
  const range = document.createElement('input');
  range.type = 'range';
  range.id = id;
  range.min = '0';
  range.max = String(SLIDER_STEPS);
  range.step = '1';
  range.dataset.testid = 'slider';
  range.dataset.pointer = s.pointer;
  range.setAttribute('aria-label', s.label);
  const number = document.createElement('input');
  number.type = 'number';
  number.step = 'any';
  number.className = 'slider-value';
  number.dataset.testid = 'slider-value';
  number.dataset.pointer = s.pointer;
  number.setAttribute('aria-label', `${s.label} value`);
  const scale = document.createElement('span');
  scale.className = 'slider-range muted small';
  scale.textContent = `${formatShort(s.min)} … ${formatShort(s.max)}${s.scale === 'log' ? ' (log)' : ''}`;
  row.append(label, number, range, scale);
  row.range = range;
  row.number = number;
  setSliderRow(row, sliderCurrent(s));

  const release = () => {
    if (state.activeSlider !== s.pointer) return;
    state.activeSlider = null;
    if (state.pendingSliders) {
      const pending = state.pendingSliders;
      state.pendingSliders = null;
      renderSliders(pending);
    }
    finishDrag();
  };
  range.addEventListener('pointerdown', () => (state.activeSlider = s.pointer));
  range.addEventListener('pointerup', release);
  range.addEventListener('pointercancel', release);
  range.addEventListener('change', release);
  range.addEventListener('input', () => {
    if (!controlsCurrent()) return;
    const v = sliderValue(row.slider, Number(range.value));
    number.value = formatShort(v);
    edit(s.pointer, v);
  });
  number.addEventListener('change', () => {
    if (!controlsCurrent()) return;
    const v = Number(number.value);
    if (number.value.trim() === '' || !Number.isFinite(v)) {
      setSliderRow(row, sliderCurrent(row.slider));
      return;
    }
    range.value = String(sliderPosition(row.slider, v));
    edit(s.pointer, v, 0);
  });
  return row;
}

// ------------------------------------------------------------ compare

function clearCompare() {
  const table = $('compare-table');
  table.hidden = true;
  table.tHead.replaceChildren();
  table.tBodies[0].replaceChildren();
  $('compare-note').hidden = true;
}

function markCompareStale() {
  const stale = !$('compare-table').hidden && (state.compareEpoch !== state.epoch || state.compareVersion !== state.version);
  $('compare-note').hidden = !stale;
  $('compare-table').classList.toggle('stale', stale);
}

async function compare() {
  if (!state.scene) return;
  const button = $('compare');
  button.disabled = true;
  const epoch = state.epoch;
  const version = state.version;
  setStatus('Comparing…');
  try {
    const res = await postJson('api/compare', { scene: state.scene });
    if (!res.ok) {
      showError(await readError(res));
      setStatus('The comparison failed.');
      return;
    }
    const { columns, rows } = await res.json();
    const table = $('compare-table');
    const head = document.createElement('tr');
    for (const c of columns) {
      const th = document.createElement('th');
      th.scope = 'col';
      th.textContent = c;
      head.append(th);
    }
    table.tHead.replaceChildren(head);
    table.tBodies[0].replaceChildren(
      ...rows.map((r) => {
        const tr = document.createElement('tr');
        r.forEach((v, k) => {
          const cell = document.createElement(k === 0 ? 'th' : 'td');
          if (k === 0) cell.scope = 'row';
          cell.textContent = typeof v === 'number' ? formatNumber(v) : v === null ? '—' : String(v);
          if (typeof v === 'number') cell.title = String(v);
          tr.append(cell);
        });
        return tr;
      }),
    );
    table.hidden = false;
    state.compareEpoch = epoch;
    state.compareVersion = version;
    markCompareStale();
    setStatus('Comparison done.');
  } catch (err) {
    showError(networkError(err));
  } finally {
    button.disabled = state.lastResponse?.kind !== 'tensor';
  }
}

// ------------------------------------------------------------ downloads

function saveScene() {
  if (!state.scene) return;
  const blob = new Blob([JSON.stringify(state.scene, null, 1) + '\n'], { type: 'application/json' });
  downloadBlob(blob, `${baseName(state.fileName)}.json`);
}

function saveResult() {
  const result = state.lastResponse?.result;
  if (!result) return;
  const blob = new Blob([JSON.stringify(result, null, 1) + '\n'], { type: 'application/json' });
  downloadBlob(blob, `${baseName(state.fileName)}.result.json`);
}

async function exportAs(format, button) {
  if (!state.scene) return;
  button.disabled = true;
  setStatus(`Exporting ${format.toUpperCase()}…`);
  try {
    const res = await postJson(`api/export?format=${encodeURIComponent(format)}`, { scene: state.scene });
    if (!res.ok) {
      showError(await readError(res));
      setStatus(`The ${format.toUpperCase()} export failed.`);
      return;
    }
    const blob = await res.blob();
    const name = dispositionFilename(res.headers.get('content-disposition')) || `${baseName(state.fileName)}.${format}`;
    downloadBlob(blob, name);
    setStatus(`Exported ${name} (${blob.size.toLocaleString()} bytes).`);
  } catch (err) {
    showError(networkError(err));
  } finally {
    button.disabled = false;
  }
}

// ------------------------------------------------------------ wiring

const VISIBILITY_KEY = 'fairsurf.editor.visibility';

function initToggles() {
  let saved = {};
  try {
    saved = JSON.parse(localStorage.getItem(VISIBILITY_KEY) || '{}');
  } catch {
    /* private mode or garbage: defaults */
  }
  for (const box of document.querySelectorAll('#toggles input[data-layer]')) {
    const layer = box.dataset.layer;
    if (typeof saved[layer] === 'boolean') box.checked = saved[layer];
    viewer.setVisible(layer, box.checked);
    box.addEventListener('change', () => {
      viewer.setVisible(layer, box.checked);
      if (layer === 'surface') renderLegend(state.lastResponse?.mesh?.legend);
      try {
        localStorage.setItem(VISIBILITY_KEY, JSON.stringify(viewer.visibility));
      } catch {
        /* not persisted */
      }
    });
  }
}

function initControls() {
  $('examples').addEventListener('change', (e) => {
    if (e.target.value) loadExample(e.target.value);
  });
  $('file-input').addEventListener('change', (e) => {
    const file = e.target.files?.[0];
    e.target.value = ''; // the same file can be loaded again
    if (file) loadFile(file);
  });
  $('save-scene').addEventListener('click', saveScene);
  $('save-result').addEventListener('click', saveResult);
  for (const button of document.querySelectorAll('#exports button[data-format]')) {
    button.addEventListener('click', () => exportAs(button.dataset.format, button));
  }
  $('compare').addEventListener('click', compare);
  $('method').addEventListener('change', (e) => {
    const pointer = e.target.dataset.pointer;
    if (pointer && controlsCurrent()) edit(pointer, e.target.value, 0);
  });
  $('error-close').addEventListener('click', clearError);
  $('frame').addEventListener('click', () => viewer.frame());
  window.addEventListener('keydown', (e) => {
    if (e.target.closest?.('input, select, textarea') || e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key === 'f' || e.key === 'F') viewer.frame();
  });
  // Let a scene file be dropped anywhere on the page.
  window.addEventListener('dragover', (e) => e.preventDefault());
  window.addEventListener('drop', (e) => {
    e.preventDefault();
    const file = e.dataTransfer?.files?.[0];
    if (file) loadFile(file);
  });
}

async function loadExampleList() {
  const select = $('examples');
  let examples;
  try {
    const res = await fetch('api/examples');
    if (!res.ok) throw Object.assign(new Error('list'), { body: await readError(res) });
    examples = (await res.json()).examples || [];
  } catch (err) {
    select.replaceChildren(new Option('(no examples)', ''));
    showError(err.body || networkError(err));
    return [];
  }
  // Group by kind; the server's order is kept inside each group.
  const groups = new Map();
  for (const ex of examples) {
    const kind = { triangular: 'Triangular', bspline: 'B-spline' }[ex.kind] ?? 'Tensor product';
    if (!groups.has(kind)) groups.set(kind, []);
    groups.get(kind).push(ex);
  }
  const placeholder = new Option('choose an example…', '');
  placeholder.disabled = true;
  const children = [placeholder];
  for (const [kind, list] of groups) {
    const group = document.createElement('optgroup');
    group.label = kind;
    for (const ex of list) {
      const o = new Option(ex.name || ex.file, ex.file);
      o.title = ex.file;
      group.append(o);
    }
    children.push(group);
  }
  select.replaceChildren(...children);
  select.value = '';
  return examples;
}

async function start() {
  initToggles();
  initControls();
  const examples = await loadExampleList();
  const wanted = decodeURIComponent(location.hash.slice(1));
  const first = examples.find((e) => e.file === wanted) || examples[0];
  // Only if nothing was loaded meanwhile (a test hook, a dropped file).
  if (first && state.loadToken === 0) await loadExample(first.file);
}

// Test hooks (also handy from the devtools console).
window.fairsurf = {
  get scene() {
    return state.scene;
  },
  get lastResponse() {
    return state.lastResponse;
  },
  get lastError() {
    return state.lastError;
  },
  get solveCount() {
    return state.solveCount;
  },
  get dragging() {
    return dragging();
  },
  get errorCount() {
    return state.errorCount;
  },
  get renderCount() {
    return viewer.renderCount;
  },
  loadScene: (obj, fileName) => loadScene(obj, fileName),
  loadExample: (file) => loadExample(file),
  handleScreenPosition: (index) => viewer.handleScreenPosition(index),
  idle,
  getPointer: (pointer) => (state.scene ? getPointer(state.scene, pointer) : undefined),
  viewer,
  ready: null,
};
window.fairsurf.ready = start();
