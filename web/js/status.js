// The status line (is meristemd answering) and the problem box (why it refused).
import * as api from './api.js';
import { $ } from './util.js';

let problemTimer = null;

/**
 * Shows a refusal (an api.Problem) or any other error for 15 s and returns what it
 * showed: {status, title, detail, field, line, column} (line and column: where a
 * definition stopped reading, else null).
 */
export function showProblem(e) {
  console.warn('meristemd refused:', e);
  const p = e instanceof api.Problem ? e : { status: 0, title: 'Error', detail: String(e.message || e) };
  $('#problem-title').textContent = p.status ? `${p.status} ${p.title}` : p.title;
  $('#problem-detail').textContent = p.detail;
  $('#problem-field').textContent = p.field || '';
  $('#problem-field').hidden = !p.field;
  const box = $('#problem');
  box.dataset.status = String(p.status || 0);
  box.hidden = false;
  clearTimeout(problemTimer);
  problemTimer = setTimeout(() => { box.hidden = true; }, 15000);
  return { status: p.status, title: p.title, detail: p.detail, field: p.field || null,
    line: p.line ?? null, column: p.column ?? null };
}

/** Takes the problem box away (another session is shown). */
export function hideProblem() {
  clearTimeout(problemTimer);
  $('#problem').hidden = true;
}

/** Lets the problem box be dismissed. */
export function mountProblemBox() {
  $('#problem-close').addEventListener('click', () => { $('#problem').hidden = true; });
}

/** Sets the status line; `kind` (ok, warn, error, ...) styles it. */
export function setStatus(text, kind) {
  const s = $('#status');
  s.textContent = text;
  s.dataset.state = kind;
}
