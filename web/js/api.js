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
export const createSession = (preset, seed) => request('POST', 'v1/sessions', { preset, seed });
export const getSession = (id) => request('GET', `v1/sessions/${id}`);
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
  compact = false, revision = null } = {}) {
  const q = new URLSearchParams({ detail: String(detail), leaves: leaves ? '1' : '0',
    markers: markers ? '1' : '0', color });
  if (compact) {
    q.set('quantize', '1');
    q.set('texcoords', '0');
    q.set('compress', 'meshopt');
    q.set('twig_lines', '1');
  }
  if (revision !== null) q.set('revision', String(revision));   // a past tree
  return `v1/sessions/${id}/snapshot.glb?${q}`;
}

/**
 * Fetches a snapshot with If-None-Match: resolves to {buffer, etag} or {notModified: true}
 * when the ETag still matches (the tree and the options have not changed).
 */
export async function fetchSnapshot(url, etag) {
  const headers = etag ? { 'If-None-Match': etag } : {};
  const r = await fetch(url, { headers, cache: 'no-store' });
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
