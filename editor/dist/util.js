// Small helpers shared by the editor modules: JSON pointers, number
// formatting, downloads. No DOM state lives here.

/** Splits an RFC 6901 JSON pointer ("/a/b~1c/0") into its unescaped tokens. */
export function pointerTokens(pointer) {
  if (pointer === '') return [];
  if (!pointer.startsWith('/')) throw new Error(`not a JSON pointer: ${pointer}`);
  return pointer
    .slice(1)
    .split('/')
    .map((t) => t.replace(/~1/g, '/').replace(/~0/g, '~'));
}

/** The value at `pointer` in `doc`, or undefined when any step is missing. */
export function getPointer(doc, pointer) {
  let node = doc;
  for (const token of pointerTokens(pointer)) {
    if (node === null || typeof node !== 'object') return undefined;
    node = Array.isArray(node) ? node[Number(token)] : node[token];
  }
  return node;
}

/**
 * Sets the value at `pointer` in `doc` (in place), creating missing
 * intermediate objects: a slider for "/energy/normal_field/weight" works on a
 * scene without "energy". An intermediate `null` is replaced by an object too.
 */
export function setPointer(doc, pointer, value) {
  const tokens = pointerTokens(pointer);
  if (tokens.length === 0) throw new Error('cannot replace the whole scene through a pointer');
  let node = doc;
  for (let k = 0; k < tokens.length - 1; k++) {
    const key = Array.isArray(node) ? Number(tokens[k]) : tokens[k];
    if (node[key] === null || typeof node[key] !== 'object') node[key] = {};
    node = node[key];
  }
  const last = tokens[tokens.length - 1];
  node[Array.isArray(node) ? Number(last) : last] = value;
}

/**
 * Formats a table number: 6 significant digits, exponent form for small or
 * huge magnitudes. Non-numbers (a string such as a factorization name, null)
 * are shown as they are.
 */
export function formatNumber(v) {
  if (typeof v !== 'number') return v === null || v === undefined ? '—' : String(v);
  if (!Number.isFinite(v)) return String(v);
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a < 1e-3 || a >= 1e7) return v.toExponential(5).replace(/\.?0+e/, 'e');
  // toPrecision keeps trailing zeros ("1.00000"); they carry no information.
  const s = v.toPrecision(6);
  return s.includes('e') ? s : s.replace(/(\.\d*?)0+$/, '$1').replace(/\.$/, '');
}

/** A short readout for a slider value (4 significant digits). */
export function formatShort(v) {
  if (typeof v !== 'number' || !Number.isFinite(v)) return String(v);
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a < 1e-3 || a >= 1e6) return v.toExponential(2);
  return String(Number(v.toPrecision(4)));
}

/** Formats a duration in seconds as "3.1 ms" / "1.25 s". */
export function formatSeconds(s) {
  if (typeof s !== 'number' || !Number.isFinite(s)) return '';
  if (s < 1e-3) return `${(s * 1e6).toPrecision(3)} µs`;
  if (s < 1) return `${(s * 1e3).toPrecision(3)} ms`;
  return `${s.toPrecision(3)} s`;
}

/** Offers `blob` as a download named `filename`. */
export function downloadBlob(blob, filename) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = filename;
  a.style.display = 'none';
  document.body.appendChild(a);
  a.click();
  a.remove();
  // Revoke later: some browsers start the download asynchronously.
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

/** The filename of a Content-Disposition header, or null. */
export function dispositionFilename(header) {
  if (!header) return null;
  const star = /filename\*\s*=\s*(?:UTF-8|utf-8)''([^;]+)/.exec(header);
  if (star) {
    try {
      return decodeURIComponent(star[1].trim());
    } catch {
      /* fall through to the plain form */
    }
  }
  const plain = /filename\s*=\s*"([^"]*)"|filename\s*=\s*([^;\s]+)/.exec(header);
  return plain ? plain[1] ?? plain[2] : null;
}

/** "wu_yang_fig1.json" → "wu_yang_fig1"; also strips ".result". */
export function baseName(file) {
  return (file || 'scene').replace(/^.*[\\/]/, '').replace(/\.json$/i, '').replace(/\.result$/i, '') || 'scene';
}

/** Converts an sRGB component (0..1) to linear light, as three.js expects for vertex colours. */
export function srgbToLinear(c) {
  return c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4);
}

/** Rounds a coordinate to `quantum` (a power of ten) so saved scenes stay readable. */
export function roundTo(v, quantum) {
  if (!(quantum > 0)) return v;
  const digits = Math.max(0, Math.min(15, -Math.floor(Math.log10(quantum))));
  return Number((Math.round(v / quantum) * quantum).toFixed(digits));
}

/**
 * The mesh of an answer with its arrays as typed arrays: base64 text
 * (`"encoding": "base64"`: little-endian float32 positions, uint16 or
 * uint32 indices as `index_type` says, uint8 sRGB colours) decoded, the
 * colours to 0..1 like a JSON mesh's; JSON lists as they are.
 * Little-endian is what every platform a browser runs on uses.
 */
export function decodeMesh(mesh) {
  if (!mesh || mesh.encoding !== 'base64') return mesh;
  const bytes = (text) => {
    const bin = atob(text);
    const out = new Uint8Array(bin.length);
    for (let k = 0; k < bin.length; k++) out[k] = bin.charCodeAt(k);
    return out.buffer;
  };
  const positions = new Float32Array(bytes(mesh.positions));
  const Index = mesh.index_type === 'uint32' ? Uint32Array : Uint16Array;
  return {
    ...mesh,
    positions,
    indices: mesh.grid ? gridIndices(mesh.grid[0], mesh.grid[1]) : new Index(bytes(mesh.indices)),
    colors: Float32Array.from(new Uint8Array(bytes(mesh.colors)), (c) => c / 255),
  };
}

/**
 * The triangles of a rows × cols grid of vertices (row-major), as the
 * server meshes a tensor surface: each cell (i, j) split into
 * (i,j)(i+1,j)(i+1,j+1) and (i,j)(i+1,j+1)(i,j+1).
 */
export function gridIndices(rows, cols) {
  const Index = rows * cols > 65536 ? Uint32Array : Uint16Array;
  const out = new Index(6 * Math.max(0, rows - 1) * Math.max(0, cols - 1));
  let k = 0;
  for (let i = 0; i + 1 < rows; i++) {
    for (let j = 0; j + 1 < cols; j++) {
      const a = i * cols + j;
      const b = a + cols;
      out.set([a, b, b + 1, a, b + 1, a + 1], k);
      k += 6;
    }
  }
  return out;
}

/** Whether `x` is a list of numbers: an array or a typed array. */
export function isList(x) {
  return Array.isArray(x) || ArrayBuffer.isView(x);
}
