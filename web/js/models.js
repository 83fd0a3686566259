// The growth models a session may name (docs/design.md: one skeleton, several models),
// and which parts of the page each one uses. A panel section or a tool button that only
// some models use says which: data-models="p09 runions" in index.html, or a tool's
// `models` list; showModel() hides it for the others.
import { $ } from './util.js';

/** id: the session's "model"; firstPreset: the preset the top bar offers first. */
export const MODELS = [
  { id: 'p09', label: 'self-organizing (P09)', firstPreset: 'fig15-brushed' },
  { id: 'lsystem', label: 'L-system (ABOP)', firstPreset: 'abop-2.6a' },
  { id: 'inverse', label: 'inverse (G04)', firstPreset: 'populus-deltoides' },
  { id: 'runions', label: 'space colonization (R07)', firstPreset: 'runions-2007' },
  { id: 'guiding', label: 'guiding vectors (XM15)', firstPreset: 'gv-fig2-small-5' },
  // No preset of its own: the top bar asks for the plants, their spacing and presets.
  { id: 'forest', label: 'sown forest (Poisson/Voronoi)', firstPreset: null, sown: true },
];

/**
 * Shows the parts of the page model `model` uses and hides the others; a tool of
 * another model that was active gives way to the first tool (`setTool`).
 */
export function showModel(model, { tools = [], activeTool = null, setTool = null } = {}) {
  document.body.dataset.model = model;
  for (const el of document.querySelectorAll('[data-models]')) {
    el.hidden = !el.dataset.models.split(/\s+/).includes(model);
  }
  for (const t of tools) {
    const b = $(`#tools [data-tool="${t.id}"]`);
    if (b && t.models) b.hidden = !t.models.includes(model);
  }
  const active = tools.find((t) => t.id === activeTool);
  if (active?.models && !active.models.includes(model) && setTool) setTool(tools[0].id);
}

/** Whether tool `t` applies to model `model`. */
export const toolApplies = (t, model) => !t.models || t.models.includes(model);
