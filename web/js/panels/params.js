// The Parameters panel: the model's key parameters with the paper's symbols
// (Palubicki et al. 2009, §4), each shown only where the chosen environment and bud-fate
// models use it. Its rows come from GET /v1/presets (ranges and defaults).
import { $ } from '../util.js';

/**
 * The parameters the page edits, by model: name, the paper's symbol and a one-line
 * explanation. `when` says which model makes a parameter active.
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
];

export class ParamsPanel {
  id = 'params';

  constructor({ session }) {
    this.root = $('#params');
    this.inputs = new Map();
    this.values = {};
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

  /** Shows a session's values (summary.params). */
  show({ params }) {
    if (!params) return;
    this.values = { ...params };
    for (const [name, { input }] of this.inputs) {
      if (name in params && document.activeElement !== input) input.value = String(params[name]);
    }
    this.updateVisibility();
  }

  updateVisibility() {
    const current = (n) => Number(this.inputs.get(n)?.input.value ?? this.values[n]);
    for (const { def, row } of this.inputs.values()) {
      const on = !def.when || Object.entries(def.when).every(([k, v]) => current(k) === v);
      row.hidden = !on;
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
