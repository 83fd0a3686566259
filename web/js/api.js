// The HTTP contract of meristemd (proto/README.md), as the page uses it.
// Every refusal is application/problem+json; it surfaces as a Problem error.

/** A refusal from meristemd: RFC 9457 problem details (type, title, status, detail, field). */
export class Problem extends Error {
  constructor(problem, status) {
    super(problem.detail || problem.title || `HTTP ${status}`);
    this.name = 'Problem';
    this.status = problem.status || status;
    this.title = problem.title || '';
    this.type = problem.type || '';
    this.detail = problem.detail || '';
    this.field = problem.field || null;
    this.line = problem.line ?? null;       // a definition's refusal: where it stopped reading
    this.column = problem.column ?? null;
  }
}

async function request(method, path, body, extraHeaders = {}) {
  const init = { method, headers: { ...extraHeaders } };
  if (body !== undefined) {
    init.body = JSON.stringify(body);
    init.headers['Content-Type'] = 'application/json';
  }
  const r = await fetch(path, init);
  const type = r.headers.get('content-type') || '';
  if (!r.ok) {
    if (type.includes('json')) throw new Problem(await r.json(), r.status);
    throw new Problem({ title: r.statusText, detail: `${method} ${path}: HTTP ${r.status}` }, r.status);
  }
  if (r.status === 204) return null;
  return type.includes('json') ? r.json() : r;
}

export const health = () => request('GET', 'v1/health');
export const presets = () => request('GET', 'v1/presets');
/** Creates a session: {preset, seed} and, for a model's own definition, model and lsystem
 * ({source}) or inverse ({fset}). A definition that does not read is a Problem with
 * `line` and `column`. */
export const createSession = (spec) => request('POST', 'v1/sessions', spec);
export const getSession = (id) => request('GET', `v1/sessions/${id}`);
/** An inverse session's functions: {functions: [{name, kind, samples, points: [[x, y, m]]}]}. */
export const functions = (id) => request('GET', `v1/sessions/${id}/functions?format=json`);
/** The URL of an inverse session's functions as .fset text (a download). */
export const functionsUrl = (id) => `v1/sessions/${id}/functions`;
/** An L-system session's cpfg source: {source}. */
export const lsystemSource = (id) => request('GET', `v1/sessions/${id}/lsystem`);
export const cancel = (id) => request('POST', `v1/sessions/${id}/cancel`, {});

/** A page of the session's revisions after `after` (null: from the first). */
export function revisions(id, after = null, limit = 1000) {
  const q = new URLSearchParams({ limit: String(limit) });
  if (after !== null) q.set('after', String(after));
  return request('GET', `v1/sessions/${id}/revisions?${q}`);
}

/** Sends one edit or a batch ({edits: [...]}); resolves to the new summary. */
export function edit(id, edits) {
  const body = Array.isArray(edits) ? (edits.length === 1 ? edits[0] : { edits }) : edits;
  return request('POST', `v1/sessions/${id}/edits`, body);
}

/** The session's living internodes: {revision, nodes: [{id, parent, order, base, tip, ...}]}. */
export function skeleton(id) {
  return request('GET', `v1/sessions/${id}/skeleton?alive=1`);
}

/**
 * The snapshot URL for the given view options. The viewer asks for `compact` ones:
 * KHR_mesh_quantization, EXT_meshopt_compression and no UVs, a third of the bytes; a
 * download gets the default (float, uncompressed, no node transform), which Blender,
 * assimp and every other glTF importer read.
 */
export function snapshotUrl(id, { detail = 3, leaves = false, markers = false, color = 'none',
  compact = false, revision = null, t = null, junctions = false } = {}) {
  const q = new URLSearchParams({ detail: String(detail), leaves: leaves ? '1' : '0',
    markers: markers ? '1' : '0', color });
  if (junctions) q.set('junctions', 'implicit');  // forks as implicit surfaces (slow on big trees)
  if (compact) {
    q.set('quantize', '1');
    q.set('texcoords', '0');
    q.set('compress', 'meshopt');
    q.set('twig_lines', '1');
  }
  if (revision !== null) q.set('revision', String(revision));   // a past tree
  if (t !== null) q.set('t', String(t));                         // an inverse tree at a fractional year
  return `v1/sessions/${id}/snapshot.glb?${q}`;
}

/**
 * Fetches a snapshot with If-None-Match: resolves to {buffer, etag} or {notModified: true}
 * when the ETag still matches (the tree and the options have not changed). An AbortSignal
 * cancels it (an AbortError).
 */
export async function fetchSnapshot(url, etag, signal = undefined) {
  const headers = etag ? { 'If-None-Match': etag } : {};
  const r = await fetch(url, { headers, cache: 'no-store', signal });
  if (r.status === 304) {
    await r.arrayBuffer();   // finish the (empty) body, or Chromium counts the request as aborted
    return { notModified: true, etag };
  }
  if (!r.ok) {
    const type = r.headers.get('content-type') || '';
    if (type.includes('json')) throw new Problem(await r.json(), r.status);
    throw new Problem({ detail: `snapshot: HTTP ${r.status}` }, r.status);
  }
  return { buffer: await r.arrayBuffer(), etag: r.headers.get('ETag') };
}
