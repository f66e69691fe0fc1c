// A stand-in for `fairsurf serve`: implements the HTTP API of editor/API.md
// with fake geometry and fake energies, and serves editor/dist. It is for
// developing the page and running the browser test without the Rust server;
// nothing here is the real mathematics.
//
//   node editor/tests/mock-server.mjs [PORT]        (default 8787)
//   MOCK_DELAY_MS=200 node editor/tests/mock-server.mjs 8787   (slow solves)

import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const DIST = path.resolve(here, '../dist');
const EXAMPLES = path.resolve(here, '../../examples');
const PORT = Number(process.argv[2] || 8787);
const DELAY_MS = Number(process.env.MOCK_DELAY_MS || 0);
const MAX_BODY = 16 << 20;
const METHODS = ['minimize', 'harmonic', 'biharmonic', 'harmonic_mask', 'biharmonic_mask'];
const FORMATS = ['obj', 'stl', 'ply', 'gltf', 'step', 'iges', 'json'];

const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json',
  '.png': 'image/png',
  '.svg': 'image/svg+xml',
};

/** An API error: HTTP status plus the `{error, path}` body. */
class ApiError extends Error {
  constructor(status, error, path = null) {
    super(error);
    this.status = status;
    this.path = path;
  }
}
const bad = (path, msg) => new ApiError(400, `${path}: ${msg}`, path);

// ------------------------------------------------------------ validation

function isPoint(p) {
  return Array.isArray(p) && p.length === 3 && p.every((x) => typeof x === 'number' && Number.isFinite(x));
}

function typeName(v) {
  if (v === null) return 'null';
  if (Array.isArray(v)) return 'sequence';
  if (typeof v === 'object') return 'map';
  return `${typeof v} ${JSON.stringify(v)}`;
}

function readScene(body) {
  if (body === null || typeof body !== 'object' || Array.isArray(body)) throw new ApiError(400, 'the request body must be an object {"scene": ...}');
  if (!('scene' in body)) throw new ApiError(400, 'missing field `scene`');
  const scene = body.scene;
  if (scene === null || typeof scene !== 'object' || Array.isArray(scene)) throw new ApiError(400, `invalid type: ${typeName(scene)}, expected a scene object`);
  const s = scene.surface;
  if (s === undefined) throw new ApiError(400, 'missing field `surface`', null);
  if (s === null || typeof s !== 'object') throw bad('surface', `invalid type: ${typeName(s)}, expected struct SurfaceSpec`);
  if (s.type !== 'tensor' && s.type !== 'triangular') throw bad('surface.type', `unknown variant ${JSON.stringify(s.type)}, expected \`tensor\` or \`triangular\``);
  return scene;
}

function parseTensor(scene) {
  const s = scene.surface;
  const d = s.degree;
  if (!Array.isArray(d) || d.length !== 2 || !d.every((x) => Number.isInteger(x))) {
    throw bad('surface.degree', `invalid type: ${typeName(d)}, expected an array of length 2`);
  }
  const [n, m] = d;
  if (n < 1 || m < 1 || n > 40 || m > 40) throw bad('surface.degree', `degree ${n}x${m} is outside 1..40`);
  const cps = s.control_points;
  if (!Array.isArray(cps) || cps.length !== n + 1) throw bad('surface.control_points', `expected ${n + 1} rows for degree ${n}`);
  cps.forEach((row, i) => {
    if (!Array.isArray(row) || row.length !== m + 1) throw bad(`surface.control_points[${i}]`, `expected ${m + 1} points for degree ${m}`);
    row.forEach((p, j) => {
      if (p !== null && !isPoint(p)) throw bad(`surface.control_points[${i}][${j}]`, `invalid value: ${JSON.stringify(p)}, expected a point [x, y, z] or null`);
    });
  });
  const method = scene.method ?? 'minimize';
  if (!METHODS.includes(method)) throw bad('method', `unknown variant ${JSON.stringify(method)}, expected one of ${METHODS.join(', ')}`);
  if (scene.fixed_rings !== undefined && !(Number.isInteger(scene.fixed_rings) && scene.fixed_rings >= 0)) {
    throw bad('fixed_rings', `invalid type: ${typeName(scene.fixed_rings)}, expected usize`);
  }
  const e = scene.energy || {};
  for (const key of ['stretch', 'bend']) {
    if (e[key] !== undefined && !(typeof e[key] === 'number' && e[key] >= 0)) throw bad(`energy.${key}`, `expected a number >= 0`);
  }
  return { n, m, cps, method, rings: scene.fixed_rings ?? 0, energy: e };
}

// ------------------------------------------------------------ fake tensor solve

function bernsteinRow(n, t) {
  const b = new Array(n + 1).fill(0);
  b[0] = 1;
  for (let j = 1; j <= n; j++) {
    let saved = 0;
    for (let k = 0; k < j; k++) {
      const tmp = b[k];
      b[k] = saved + (1 - t) * tmp;
      saved = t * tmp;
    }
    b[j] = saved;
  }
  return b;
}

function evalTensor(net, u, v) {
  const n = net.length - 1;
  const m = net[0].length - 1;
  const bu = bernsteinRow(n, u);
  const bv = bernsteinRow(m, v);
  const p = [0, 0, 0];
  for (let i = 0; i <= n; i++) {
    for (let j = 0; j <= m; j++) {
      const w = bu[i] * bv[j];
      for (let c = 0; c < 3; c++) p[c] += w * net[i][j][c];
    }
  }
  return p;
}

function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
function scale(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
function norm(a) { return Math.sqrt(dot(a, a)); }

function fakeTensorSolve(scene) {
  const { n, m, cps, method, rings, energy } = parseTensor(scene);
  const freeSet = new Set((scene.free_points || []).map(([i, j]) => `${i},${j}`));
  const isFree = (i, j) => (rings > 0 ? Math.min(i, n - i, j, m - j) >= rings : cps[i][j] === null || freeSet.has(`${i},${j}`));
  // Fixed points must be given.
  for (let i = 0; i <= n; i++) for (let j = 0; j <= m; j++) {
    if (!isFree(i, j) && cps[i][j] === null) throw new ApiError(422, `surface.control_points[${i}][${j}]: a fixed control point has no value`, `surface.control_points[${i}][${j}]`);
  }
  // Start from a bilinear blend of the corners where nothing is given.
  const corner = (a, b) => cps[a][b] || [a / n, b / m, 0];
  const net = [];
  for (let i = 0; i <= n; i++) {
    net.push([]);
    for (let j = 0; j <= m; j++) {
      const u = i / n, v = j / m;
      const bil = add(add(scale(corner(0, 0), (1 - u) * (1 - v)), scale(corner(n, 0), u * (1 - v))), add(scale(corner(0, m), (1 - u) * v), scale(corner(n, m), u * v)));
      net[i].push((cps[i][j] || bil).slice());
    }
  }
  // "Solve": Jacobi sweeps of the discrete Laplacian over the free points,
  // then a bump whose height depends on the weights, so that sliders and
  // dragged points visibly change the answer.
  const lambda = Number(energy.normal_field?.weight ?? 0) || 0;
  const gamma = Number(energy.guide_surface?.weight ?? 0) || 0;
  const stretchW = energy.stretch ?? (energy.bend === undefined ? 1 : 0);
  const bendW = energy.bend ?? 0;
  for (let sweep = 0; sweep < 60; sweep++) {
    for (let i = 1; i < n; i++) for (let j = 1; j < m; j++) {
      if (!isFree(i, j)) continue;
      net[i][j] = scale(add(add(net[i - 1][j], net[i + 1][j]), add(net[i][j - 1], net[i][j + 1])), 0.25);
    }
  }
  const methodBump = { minimize: 1, harmonic: 0.6, biharmonic: 1.4, harmonic_mask: 0.5, biharmonic_mask: 1.2 }[method];
  const bump = 0.08 * Math.log10(1 + lambda) * methodBump - 0.0005 * gamma + 0.02 * bendW;
  for (let i = 0; i <= n; i++) for (let j = 0; j <= m; j++) {
    if (isFree(i, j)) net[i][j][2] += bump * Math.sin((Math.PI * i) / n) * Math.sin((Math.PI * j) / m);
  }

  // Mesh: a (g+1)² grid, coloured by a fake curvature (height over the
  // boundary's mean plane would do; use z).
  const g = 24;
  const positions = [];
  const grid = [];
  for (let a = 0; a <= g; a++) {
    grid.push([]);
    for (let b = 0; b <= g; b++) {
      const p = evalTensor(net, a / g, b / g);
      grid[a].push(p);
      positions.push(...p);
    }
  }
  const indices = [];
  for (let a = 0; a < g; a++) for (let b = 0; b < g; b++) {
    const k = a * (g + 1) + b;
    indices.push(k, k + g + 1, k + 1, k + 1, k + g + 1, k + g + 2);
  }
  const { colors, legend } = colorBy(positions.filter((_, k) => k % 3 === 2), 'mean curvature (mock)');

  let area = 0;
  for (let k = 0; k < indices.length; k += 3) {
    const p = positions.slice(indices[k] * 3, indices[k] * 3 + 3);
    const q = positions.slice(indices[k + 1] * 3, indices[k + 1] * 3 + 3);
    const r = positions.slice(indices[k + 2] * 3, indices[k + 2] * 3 + 3);
    area += norm(cross(sub(q, p), sub(r, p))) / 2;
  }
  let stretch = 0, bend = 0;
  for (let i = 0; i <= n; i++) for (let j = 0; j <= m; j++) {
    if (i < n) stretch += dot(sub(net[i + 1][j], net[i][j]), sub(net[i + 1][j], net[i][j])) * n;
    if (j < m) stretch += dot(sub(net[i][j + 1], net[i][j]), sub(net[i][j + 1], net[i][j])) * m;
    if (i > 0 && i < n) { const d = add(sub(net[i + 1][j], scale(net[i][j], 2)), net[i - 1][j]); bend += dot(d, d) * n * n; }
  }
  stretch /= 2;
  bend /= 2;
  const normalE = lambda * 1e-3 * (1 + Math.abs(bump));
  const guideE = gamma * 1e-4 * bump * bump;
  const total = stretchW * stretch + bendW * bend + normalE + guideE;

  const table = [
    { label: 'stretch', value: stretch },
    { label: 'bend', value: bend },
    ...(energy.normal_field ? [{ label: 'normal field', value: normalE }] : []),
    ...(energy.guide_surface ? [{ label: 'guide surface', value: guideE }] : []),
    { label: 'energy', value: total },
    { label: 'area', value: area },
    { label: 'gradient (relative)', value: 3.2e-16 },
    { label: 'condition estimate', value: 1.7e4 * n * m },
  ];

  const points = net.flat();
  const edges = [];
  for (let i = 0; i <= n; i++) for (let j = 0; j <= m; j++) {
    const k = i * (m + 1) + j;
    if (j < m) edges.push([k, k + 1]);
    if (i < n) edges.push([k, k + m + 1]);
  }
  const boundary = [
    grid[0],
    grid.map((row) => row[g]),
    grid[g].slice().reverse(),
    grid.map((row) => row[0]).reverse(),
  ];

  const normals = [];
  if (energy.normal_field) {
    const size = norm(sub(net[n][m], net[0][0])) || 1;
    for (let a = 1; a < 6; a++) for (let b = 1; b < 6; b++) {
      const u = a / 6, v = b / 6;
      const p = evalTensor(net, u, v);
      const du = sub(evalTensor(net, Math.min(1, u + 1e-4), v), evalTensor(net, Math.max(0, u - 1e-4), v));
      const dv = sub(evalTensor(net, u, Math.min(1, v + 1e-4)), evalTensor(net, u, Math.max(0, v - 1e-4)));
      const nn = cross(du, dv);
      normals.push({ at: p, dir: scale(nn, (0.08 * size) / (norm(nn) || 1)) });
    }
  }

  const handles = [];
  for (let i = 0; i <= n; i++) for (let j = 0; j <= m; j++) {
    if (!isFree(i, j)) handles.push({ pointer: `/surface/control_points/${i}/${j}`, position: net[i][j], label: `P(${i},${j})`, kind: 'control_point' });
  }

  const sliders = [];
  if (method === 'minimize') {
    if (energy.stretch !== undefined || energy.bend === undefined) sliders.push({ pointer: '/energy/stretch', label: 'stretch weight', value: energy.stretch ?? 1, min: 0, max: 10, scale: 'linear' });
    if (energy.bend !== undefined) sliders.push({ pointer: '/energy/bend', label: 'bend weight', value: energy.bend, min: 0, max: 10, scale: 'linear' });
    if (energy.normal_field) sliders.push({ pointer: '/energy/normal_field/weight', label: 'λ normal field', value: lambda, min: 0.1, max: 1000, scale: 'log' });
    if (energy.guide_surface) sliders.push({ pointer: '/energy/guide_surface/weight', label: 'γ guide surface', value: gamma, min: 0, max: 1000, scale: 'linear' });
  }

  const result = structuredClone(scene);
  result.surface.control_points = net;
  result.report = { mock: true, energy: total, area };

  return {
    kind: 'tensor',
    table,
    result,
    mesh: { positions, indices, colors, legend },
    net: { points, edges },
    boundary,
    normals,
    operators: [],
    handles,
    sliders,
    methods: { pointer: '/method', value: method, options: METHODS },
  };
}

/** Colours values through a cool-to-warm map (sRGB 0..1), with its legend. */
function colorBy(values, name) {
  let min = Math.min(...values);
  let max = Math.max(...values);
  if (!(max > min)) { min -= 1; max += 1; }
  const stops = [[0, '#3b4cc0'], [0.5, '#dddddd'], [1, '#b40426']];
  const rgb = stops.map(([, h]) => [1, 3, 5].map((k) => parseInt(h.slice(k, k + 2), 16) / 255));
  const colors = [];
  for (const v of values) {
    const t = (v - min) / (max - min);
    const [a, b, s] = t < 0.5 ? [rgb[0], rgb[1], t * 2] : [rgb[1], rgb[2], t * 2 - 1];
    colors.push(a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s, a[2] + (b[2] - a[2]) * s);
  }
  return { colors, legend: { name, min, max, stops } };
}

// ------------------------------------------------------------ fake triangular solve

function fakeTriangularSolve(scene) {
  const s = scene.surface;
  if (!Number.isInteger(s.degree) || s.degree < 1 || s.degree > 20) throw bad('surface.degree', `invalid value: ${JSON.stringify(s.degree)}, expected a degree 1..20`);
  if (!Array.isArray(s.vertices) || s.vertices.length < 3) throw bad('surface.vertices', 'expected at least 3 vertices');
  s.vertices.forEach((p, k) => { if (!isPoint(p)) throw bad(`surface.vertices[${k}]`, `invalid value: ${JSON.stringify(p)}, expected [x, y, z]`); });
  if (!Array.isArray(s.triangles) || s.triangles.length < 1) throw bad('surface.triangles', 'expected at least one triangle');
  s.triangles.forEach((t, k) => {
    if (!Array.isArray(t) || t.length !== 3 || !t.every((i) => Number.isInteger(i) && i >= 0 && i < s.vertices.length)) throw bad(`surface.triangles[${k}]`, 'expected three vertex indices');
  });
  const V = s.vertices;
  const T = s.triangles;
  const ops = Array.isArray(scene.operators) ? scene.operators : [];
  const energy = scene.energy || {};

  // A fake displacement: each attractor pulls the surface towards its point
  // with a Gaussian falloff scaled by its strength.
  const size = Math.max(...[0, 1, 2].map((c) => Math.max(...V.map((p) => p[c])) - Math.min(...V.map((p) => p[c])))) || 1;
  const bendW = energy.bend ?? 1;
  const centroid = (t) => scale(add(add(V[t[0]], V[t[1]]), V[t[2]]), 1 / 3);
  const opAt = (op) => {
    if (op.at && Number.isInteger(op.at.triangle) && T[op.at.triangle]) return centroid(T[op.at.triangle]);
    if (Array.isArray(op.domain_region) && op.domain_region.length) {
      const c = op.domain_region.reduce((a, q) => [a[0] + q[0], a[1] + q[1]], [0, 0]).map((x) => x / op.domain_region.length);
      return [c[0], c[1], 0];
    }
    return Array.isArray(op.point) ? op.point.slice() : null;
  };
  const displace = (p) => {
    let dz = 0;
    for (const op of ops) {
      const at = opAt(op);
      if (!at || !isPoint(op.point)) continue;
      const w = (Number(op.strength) || 0) / (Number(op.strength) + 20 * bendW + 1e-9);
      const r2 = ((p[0] - at[0]) ** 2 + (p[1] - at[1]) ** 2) / (0.08 * size * size);
      dz += w * (op.point[2] - at[2]) * Math.exp(-r2);
    }
    return [p[0], p[1], p[2] + dz];
  };

  const sdiv = 6;
  const positions = [];
  const indices = [];
  for (const t of T) {
    const [a, b, c] = t.map((i) => V[i]);
    const base = positions.length / 3;
    const idx = (i, j) => base + (i * (2 * sdiv + 3 - i)) / 2 + j;
    for (let i = 0; i <= sdiv; i++) for (let j = 0; j <= sdiv - i; j++) {
      const u = i / sdiv, v = j / sdiv;
      positions.push(...displace(add(add(scale(a, 1 - u - v), scale(b, u)), scale(c, v))));
    }
    for (let i = 0; i < sdiv; i++) for (let j = 0; j < sdiv - i; j++) {
      indices.push(idx(i, j), idx(i + 1, j), idx(i, j + 1));
      if (j < sdiv - i - 1) indices.push(idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
    }
  }
  const { colors, legend } = colorBy(positions.filter((_, k) => k % 3 === 2), 'mean curvature (mock)');

  const edgeCount = new Map();
  for (const t of T) for (let k = 0; k < 3; k++) {
    const a = t[k], b = t[(k + 1) % 3];
    const key = a < b ? `${a},${b}` : `${b},${a}`;
    edgeCount.set(key, (edgeCount.get(key) || 0) + 1);
  }
  const edges = [...edgeCount.keys()].map((k) => k.split(',').map(Number));
  const boundaryEdges = edges.filter(([a, b]) => edgeCount.get(`${a},${b}`) === 1);
  const onBoundary = new Set(boundaryEdges.flat());
  const points = V.map(displace);

  const handles = [];
  V.forEach((p, k) => { if (onBoundary.has(k)) handles.push({ pointer: `/surface/vertices/${k}`, position: p, label: `vertex ${k}`, kind: 'control_point' }); });
  const operators = [];
  ops.forEach((op, k) => {
    const at = opAt(op);
    if (!at) return;
    operators.push({ name: op.name || `operator ${k}`, kind: op.type || 'operator', at: displace(at), target: isPoint(op.point) ? op.point : null });
    if (isPoint(op.point)) handles.push({ pointer: `/operators/${k}/point`, position: op.point, label: `${op.name || 'operator'} target`, kind: 'operator' });
    // A direction: drawn 0.15 from where it acts, along it (API.md, handles[].edit).
    const d = op.type === 'director' && isPoint(op.direction) ? op.direction : null;
    const len = d && Math.hypot(...d);
    if (len > 0) {
      const anchor = displace(at);
      handles.push({
        pointer: `/operators/${k}/direction`,
        position: anchor.map((a, c) => a + (0.15 * d[c]) / len),
        label: `${op.name || 'operator'}: direction`,
        kind: 'operator',
        edit: { type: 'direction', anchor, length: 0.15 },
      });
    }
  });

  const sliders = [];
  if (energy.stretch !== undefined) sliders.push({ pointer: '/energy/stretch', label: 'stretch weight', value: energy.stretch, min: 0, max: 10, scale: 'linear' });
  sliders.push({ pointer: '/energy/bend', label: 'bend weight', value: bendW, min: 0.01, max: 100, scale: 'log' });
  ops.forEach((op, k) => {
    if (typeof op.strength === 'number') sliders.push({ pointer: `/operators/${k}/strength`, label: `${op.name || 'operator'} strength`, value: op.strength, min: 0.1, max: 10000, scale: 'log' });
  });

  const zs = positions.filter((_, k) => k % 3 === 2);
  const result = structuredClone(scene);
  result.report = { mock: true };
  return {
    kind: 'triangular',
    table: [
      { label: 'bend', value: Math.max(...zs) - Math.min(...zs) + 1 / bendW },
      { label: 'operators', value: ops.reduce((a, op) => a + (Number(op.strength) || 0) * 1e-3, 0) },
      // Fake, but it changes when a direction turns.
      { label: 'director angles', value: ops.reduce((a, op) => (isPoint(op.direction) ? a + Math.atan2(op.direction[1], op.direction[0]) + Math.acos(op.direction[2] / (Math.hypot(...op.direction) || 1)) : a), 0) },
      { label: 'area', value: size * size },
      { label: 'gradient (relative)', value: 2.5e-15 },
    ],
    result,
    mesh: { positions, indices, colors, legend },
    net: { points, edges },
    boundary: boundaryEdges.map(([a, b]) => [points[a], points[b]]),
    normals: [],
    operators,
    handles,
    sliders,
    methods: null,
  };
}

function solve(scene) {
  const t0 = process.hrtime.bigint();
  const out = scene.surface.type === 'triangular' ? fakeTriangularSolve(scene) : fakeTensorSolve(scene);
  out.seconds = Number(process.hrtime.bigint() - t0) / 1e9;
  return out;
}

// ------------------------------------------------------------ exports

function exportScene(scene, format) {
  const r = solve(scene);
  const name = String(scene.name || 'surface').toLowerCase().replace(/[^a-z0-9]+/g, '_').replace(/^_|_$/g, '') || 'surface';
  const P = r.mesh.positions;
  const I = r.mesh.indices;
  const tri = (k) => [0, 1, 2].map((c) => P.slice(I[k + c] * 3, I[k + c] * 3 + 3));
  switch (format) {
    case 'obj': {
      let s = `# fairsurf mock export\n`;
      for (let k = 0; k < P.length; k += 3) s += `v ${P[k]} ${P[k + 1]} ${P[k + 2]}\n`;
      for (let k = 0; k < I.length; k += 3) s += `f ${I[k] + 1} ${I[k + 1] + 1} ${I[k + 2] + 1}\n`;
      return { body: s, type: 'model/obj', file: `${name}.obj` };
    }
    case 'stl': {
      let s = `solid ${name}\n`;
      for (let k = 0; k < I.length; k += 3) {
        const [a, b, c] = tri(k);
        const nn = cross(sub(b, a), sub(c, a));
        const l = norm(nn) || 1;
        s += ` facet normal ${nn[0] / l} ${nn[1] / l} ${nn[2] / l}\n  outer loop\n`;
        for (const p of [a, b, c]) s += `   vertex ${p[0]} ${p[1]} ${p[2]}\n`;
        s += `  endloop\n endfacet\n`;
      }
      return { body: s + `endsolid ${name}\n`, type: 'model/stl', file: `${name}.stl` };
    }
    case 'ply': {
      let s = `ply\nformat ascii 1.0\nelement vertex ${P.length / 3}\nproperty float x\nproperty float y\nproperty float z\nelement face ${I.length / 3}\nproperty list uchar int vertex_indices\nend_header\n`;
      for (let k = 0; k < P.length; k += 3) s += `${P[k]} ${P[k + 1]} ${P[k + 2]}\n`;
      for (let k = 0; k < I.length; k += 3) s += `3 ${I[k]} ${I[k + 1]} ${I[k + 2]}\n`;
      return { body: s, type: 'application/octet-stream', file: `${name}.ply` };
    }
    case 'gltf':
      return { body: JSON.stringify({ asset: { version: '2.0', generator: 'fairsurf mock' }, scenes: [], nodes: [] }), type: 'model/gltf+json', file: `${name}.gltf` };
    case 'step':
      return { body: `ISO-10303-21;\nHEADER;\nFILE_NAME('${name}.step','',(''),(''),'fairsurf mock','','');\nENDSEC;\nDATA;\nENDSEC;\nEND-ISO-10303-21;\n`, type: 'application/step', file: `${name}.step` };
    case 'iges':
      return { body: `fairsurf mock IGES export${' '.repeat(47)}S      1\n`, type: 'application/iges', file: `${name}.igs` };
    case 'json':
      return { body: JSON.stringify(r.result, null, 1), type: 'application/json', file: `${name}.result.json` };
    default:
      throw new ApiError(400, `format: unknown format ${JSON.stringify(format)}, expected one of ${FORMATS.join(', ')}`, 'format');
  }
}

function compare(scene) {
  if (scene.surface.type !== 'tensor') throw new ApiError(422, 'compare: only tensor-product scenes can be compared', null);
  const rows = [];
  for (const method of METHODS) {
    const r = fakeTensorSolve({ ...scene, method, fixed_rings: scene.fixed_rings ?? 1 });
    const v = (label) => r.table.find((t) => t.label === label)?.value ?? null;
    rows.push([method === 'minimize' ? 'energy minimizer' : method.replace(/_/g, ' '), v('stretch'), v('bend'), v('area')]);
  }
  return { columns: ['surface', 'stretch', 'bend', 'area'], rows };
}

// ------------------------------------------------------------ http

function listExamples() {
  const files = fs.readdirSync(EXAMPLES).filter((f) => f.endsWith('.json')).sort();
  return files.map((file) => {
    try {
      const scene = JSON.parse(fs.readFileSync(path.join(EXAMPLES, file), 'utf8'));
      if (!scene.surface) return null; // a fill scene: for `fairsurf fill`, not the editor
      return { file, name: scene.name || file, kind: scene.surface?.type === 'triangular' ? 'triangular' : 'tensor' };
    } catch {
      return null;
    }
  }).filter(Boolean);
}

function sendJson(res, status, body) {
  const text = JSON.stringify(body);
  res.writeHead(status, { 'content-type': 'application/json', 'cache-control': 'no-store' });
  res.end(text);
}

function readBody(req) {
  return new Promise((resolve, reject) => {
    const chunks = [];
    let size = 0;
    req.on('data', (c) => {
      size += c.length;
      if (size > MAX_BODY) {
        reject(new ApiError(413, `the request body is larger than ${MAX_BODY} bytes`));
        req.destroy();
        return;
      }
      chunks.push(c);
    });
    req.on('end', () => resolve(Buffer.concat(chunks).toString('utf8')));
    req.on('error', reject);
  });
}

async function readJsonBody(req) {
  const text = await readBody(req);
  try {
    return JSON.parse(text);
  } catch (e) {
    throw new ApiError(400, `the request body is not JSON: ${e.message}`);
  }
}

function serveStatic(req, res, urlPath) {
  let rel = decodeURIComponent(urlPath);
  if (rel.endsWith('/')) rel += 'index.html';
  const file = path.resolve(DIST, '.' + rel);
  if (!file.startsWith(DIST + path.sep) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
    res.writeHead(404, { 'content-type': 'text/plain' });
    res.end('not found');
    return;
  }
  res.writeHead(200, { 'content-type': TYPES[path.extname(file)] || 'application/octet-stream', 'cache-control': 'no-cache' });
  fs.createReadStream(file).pipe(res);
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

const server = http.createServer(async (req, res) => {
  const url = new URL(req.url, 'http://localhost');
  try {
    if (url.pathname === '/api/examples' && req.method === 'GET') return sendJson(res, 200, { examples: listExamples() });
    if (url.pathname.startsWith('/api/examples/') && req.method === 'GET') {
      const file = decodeURIComponent(url.pathname.slice('/api/examples/'.length));
      if (!listExamples().some((e) => e.file === file)) throw new ApiError(404, `no example named ${JSON.stringify(file)}`);
      res.writeHead(200, { 'content-type': 'application/json' });
      return res.end(fs.readFileSync(path.join(EXAMPLES, file)));
    }
    if (url.pathname === '/api/solve' && req.method === 'POST') {
      const body = await readJsonBody(req);
      const scene = readScene(body);
      if (DELAY_MS) await sleep(DELAY_MS);
      const quick = body.quick === true;
      const answer = solve(scene);
      // A quick answer lacks the measures (here: the rows after the first two).
      return sendJson(res, 200, { ...answer, table: quick ? answer.table.slice(0, 2) : answer.table, quick });
    }
    if (url.pathname === '/api/export' && req.method === 'POST') {
      const format = url.searchParams.get('format') || '';
      if (!FORMATS.includes(format)) throw new ApiError(400, `format: unknown format ${JSON.stringify(format)}, expected one of ${FORMATS.join(', ')}`, 'format');
      const out = exportScene(readScene(await readJsonBody(req)), format);
      res.writeHead(200, { 'content-type': out.type, 'content-disposition': `attachment; filename="${out.file}"` });
      return res.end(out.body);
    }
    if (url.pathname === '/api/compare' && req.method === 'POST') {
      return sendJson(res, 200, compare(readScene(await readJsonBody(req))));
    }
    if (url.pathname.startsWith('/api/')) throw new ApiError(404, `no endpoint ${req.method} ${url.pathname}`);
    if (req.method !== 'GET' && req.method !== 'HEAD') throw new ApiError(405, `method ${req.method} not allowed`);
    return serveStatic(req, res, url.pathname);
  } catch (e) {
    if (e instanceof ApiError) return sendJson(res, e.status, { error: e.message, path: e.path });
    console.error(e);
    return sendJson(res, 500, { error: `mock server bug: ${e.message}`, path: null });
  }
});

server.listen(PORT, '127.0.0.1', () => {
  console.log(`fairsurf mock server on http://127.0.0.1:${server.address().port}/ (dist: ${DIST})`);
});
