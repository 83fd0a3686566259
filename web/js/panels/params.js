// The Parameters panel: the session's growth model's key parameters with the papers'
// symbols (Palubicki et al. 2009, §4; Runions et al. 2007; ABOP), each shown only for
// the models that read it and, for P09, where the chosen environment and bud-fate models
// use it. Its rows come from GET /v1/presets (ranges and defaults). An inverse tree's
// parameters are its functions (the Functions panel).
import { $ } from '../util.js';

/**
 * The parameters the page edits: name, the paper's symbol and a one-line explanation.
 * `models`: the growth models whose sessions show it (default: P09's alone); `when`
 * says which of P09's environment and fate models make it active.
 */
export const KEY_PARAMS = [
  { name: 'environment', label: 'environment', kind: 'choice',
    choices: [[0, 'shadow propagation (§4.1)'], [1, 'space colonization (§4.1)']],
    explain: 'How a bud senses light and space; the brush lays markers for space colonization.' },
  { name: 'fate', label: 'bud fate', kind: 'choice',
    choices: [[0, 'extended Borchert–Honda (§4.2)'], [1, 'priority model (§4.2)']],
    explain: 'How the resource gathered by the tree is shared among its buds.' },
  { name: 'lambda', symbol: 'λ', when: { fate: 0 },
    explain: 'Apical control: share of resource the main axis keeps at each branching.' },
  { name: 'alpha', symbol: 'α', when: { fate: 0 },
    explain: 'Resource at the base per unit light: v_base = α·Q_base.' },
  { name: 'w_max', symbol: 'w_max', when: { fate: 1 },
    explain: 'Weight of the best-lit branches in the priority model (Fig. 8c).' },
  { name: 'w_min', symbol: 'w_min', when: { fate: 1 },
    explain: 'Weight of the least-lit branches (Fig. 8c).' },
  { name: 'kappa', symbol: 'κ', when: { fate: 1 },
    explain: 'Fraction of branches, best-lit first, that get the highest weight.' },
  { name: 'xi', symbol: 'ξ',
    explain: 'Weight of the optimal growth direction V: the pull towards light or free space.' },
  { name: 'eta', symbol: 'η',
    explain: 'Weight of tropism: > 0 shoots bend up, < 0 they droop (Fig. 12).' },
  { name: 'theta', symbol: 'θ', when: { environment: 1 },
    explain: 'Perception angle of a bud\'s cone, in degrees (Fig. 4).' },
  { name: 'rho', symbol: 'ρ', when: { environment: 1 },
    explain: 'Occupancy radius: markers this close to a bud are removed (internodes).' },
  { name: 'r', symbol: 'r', when: { environment: 1 },
    explain: 'Perception distance of a bud (internodes).' },
  { name: 'shadow_a', symbol: 'a', when: { environment: 0 },
    explain: 'Shadow a bud casts into the voxel under it (Fig. 5).' },
  { name: 'shadow_b', symbol: 'b', when: { environment: 0 },
    explain: 'Shadow falls off as a·b^−q with depth q below the bud.' },
  { name: 'q_max', symbol: 'q_max', when: { environment: 0 },
    explain: 'Depth of the penumbra pyramid, in voxel layers.' },
  { name: 'shed_threshold', symbol: 'shed', label: 'shedding threshold',
    explain: 'A branch whose light per internode falls below this is shed (0: never).' },
  { name: 'd_i', symbol: 'd_i', label: 'influence distance', models: ['runions'],
    explain: 'A marker attracts the closest node within this distance (R07).' },
  { name: 'd_k', symbol: 'd_k', label: 'kill distance', models: ['runions'],
    explain: 'Markers this close to a node are removed; d_k < d_i.' },
  { name: 'D', symbol: 'D', label: 'node length', models: ['runions'],
    explain: 'The length of the node each attracted node grows in a step.' },
  { name: 'gv_density', label: 'node density', models: ['guiding'],
    explain: 'Graph nodes per unit volume in the crown (Xu & Mould 2015).' },
  { name: 'gv_cones', symbol: 'k', label: 'cones', models: ['guiding'],
    explain: 'Each node links to its nearest neighbour in each of k cones (a Yao graph).' },
  { name: 'gv_rotation', symbol: 'δ', label: 'rotation per hop', models: ['guiding'],
    explain: 'Degrees the guiding vector turns at the first hop from the source.' },
  { name: 'gv_rotation_falloff', label: 'rotation fall-off', models: ['guiding'],
    explain: 'The rotation at hop h is δ·fall-off^(h − 1): below 1 it fades, above 1 it grows.' },
  { name: 'gv_early_endpoints', label: 'first endpoints', models: ['guiding'],
    explain: 'Endpoints of the first iteration: one gives a trunk, several a shrub.' },
  { name: 'gv_endpoints', label: 'endpoints', models: ['guiding'],
    explain: 'Endpoints per later iteration, on the surface extrapolated from the tree.' },
  { name: 'gv_endpoints_total', label: 'endpoints in all', models: ['guiding'],
    explain: 'When above 0: the endpoints of all iterations together, each later iteration taking its share of what is left (instead of endpoints per iteration).' },
  { name: 'gv_k_hops', symbol: 'k', label: 'hops out', models: ['guiding'],
    explain: 'Later endpoints are this many hops out from the current tree.' },
  { name: 'gv_t', symbol: 't', label: 'outer fraction', models: ['guiding'],
    explain: 'Endpoints come from the outermost fraction t of those nodes.' },
  { name: 'gv_bound', label: 'bounded', kind: 'choice', models: ['guiding'],
    choices: [[0, 'endpoints anywhere'], [1, 'endpoints inside the crown volume']],
    explain: 'Whether later endpoints must lie inside the crown volume.' },
  { name: 'gv_iterations', label: 'iterations', models: ['guiding'],
    explain: 'How many iterations the tree grows (one per step).' },
  { name: 'gv_epsilon', symbol: 'ε', models: ['guiding'],
    explain: 'The floor of an edge cost |e|·(ε + (1 − g·ê)/2)^p: no edge is free.' },
  { name: 'gv_p', symbol: 'p', models: ['guiding'],
    explain: 'How sharply an edge that leaves the guiding vector is penalised.' },
  { name: 'ls_delta', symbol: 'δ', label: 'angle', models: ['lsystem'],
    explain: 'The turn of + − & ^ \\ / with no parameter, in degrees (ABOP §1.5).' },
  { name: 'ls_step', symbol: 'd', label: 'step', models: ['lsystem'],
    explain: 'The length of F with no parameter.' },
  { name: 'ls_width', symbol: 'w', label: 'width', models: ['lsystem'],
    explain: 'The segment width before any ! (0: the pipe model gives widths).' },
  { name: 'ls_width_scale', label: 'width scale', models: ['lsystem'],
    explain: 'The widths ! sets are multiplied by this.' },
  { name: 'ls_elasticity', symbol: 'e', label: 'elasticity', models: ['lsystem'],
    explain: 'Susceptibility to tropism T after each F (ABOP §2.2).' },
  { name: 'ls_blocking', label: 'blocking', kind: 'choice', models: ['lsystem'],
    choices: [[0, 'segments pass through the ground and obstacles'], [1, 'the ground and obstacles stop segments']],
    explain: 'Whether a segment whose end the ground or an obstacle holds stops its branch.' },
];

export class ParamsPanel {
  id = 'params';

  constructor({ session }) {
    this.root = $('#params');
    this.inputs = new Map();
    this.values = {};
    this.model = 'p09';
    $('#apply-params').addEventListener('click', () => {
      const changed = this.changed();
      if (!Object.keys(changed).length) return;
      session.send([{ op: 'set_params', params: changed }]);
    });
  }

  /** Builds the rows from the daemon's parameter table (GET /v1/presets: parameters). */
  presets({ parameters }) {
    this.meta = new Map(parameters.map((p) => [p.name, p]));
    for (const p of KEY_PARAMS) {
      const m = this.meta.get(p.name);
      if (m) this._addRow(p, m);
    }
  }

  /** A row for KEY_PARAMS entry `p`, whose range and default `m` gives. */
  _addRow(p, m) {
    const row = document.createElement('div');
    row.className = 'param';
    row.dataset.name = p.name;
    const label = document.createElement('label');
    const sym = document.createElement('span');
    sym.className = 'symbol';
    sym.textContent = p.symbol || '';
    // d_i, w_max: the part after the underscore as a subscript, as the papers set it.
    const [base, sub] = (p.symbol || '').split('_');
    if (sub) {
      const s = document.createElement('sub');
      s.textContent = sub;
      sym.replaceChildren(base, s);
    }
    const name = document.createElement('span');
    name.className = 'pname';
    name.textContent = p.label || p.name;
    let input;
    if (p.kind === 'choice') {
      input = document.createElement('select');
      for (const [v, text] of p.choices) input.add(new Option(text, String(v)));
      input.addEventListener('change', () => this.updateVisibility());
    } else {
      input = document.createElement('input');
      input.type = 'number';
      input.min = String(m.min);
      input.max = String(m.max);
      input.step = 'any';
    }
    input.id = `param-${p.name}`;
    input.name = p.name;
    input.title = `${p.name}: ${m.min} … ${m.max}, default ${m.default}`;
    label.append(sym, name, input);
    const explain = document.createElement('p');
    explain.className = 'explain';
    explain.textContent = p.explain;
    row.append(label, explain);
    this.root.append(row);
    this.inputs.set(p.name, { input, def: p, row });
  }

  /** Shows a session's values (summary.params: the rows its model reads). */
  show({ params, model }) {
    if (model) this.model = model;
    if (!params) return;
    this.values = { ...params };
    for (const [name, { input }] of this.inputs) {
      if (name in params && document.activeElement !== input) input.value = String(params[name]);
      else if (!(name in params)) input.value = '';
    }
    this.updateVisibility();
  }

  updateVisibility() {
    const current = (n) => Number(this.inputs.get(n)?.input.value ?? this.values[n]);
    const read = (name) => !Object.keys(this.values).length || name in this.values;
    for (const { def, row } of this.inputs.values()) {
      const mine = (def.models || ['p09']).includes(this.model) && read(def.name);
      row.hidden = !mine || (def.when && !Object.entries(def.when).every(([k, v]) => current(k) === v));
    }
  }

  /** The values the user changed: {name: number}. */
  changed() {
    const out = {};
    for (const [name, { input }] of this.inputs) {
      if (input.value === '') continue;
      const v = Number(input.value);
      if (!Number.isNaN(v) && v !== this.values[name]) out[name] = v;
    }
    return out;
  }
}
