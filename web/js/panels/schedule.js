// The Apical control panel: the step at which apical control ends on each branch
// order, and keyframes for λ and η over the steps (Palubicki et al. 2009, §4.2,
// Figs. 10-11), sent as one set_apical_schedule edit.
import { $ } from '../util.js';

const ORDERS = 8;

export class SchedulePanel {
  id = 'schedule';

  constructor({ session }) {
    this.orders = $('#apical-off');
    this.offInputs = [];
    for (let k = 0; k < ORDERS; k++) {
      const l = document.createElement('label');
      l.innerHTML = `<span>${k === 0 ? 'trunk' : `order ${k}`}</span>`;
      const i = document.createElement('input');
      i.type = 'number'; i.min = '0'; i.step = '1'; i.placeholder = 'never';
      i.id = `apical-off-${k}`;
      l.append(i);
      this.orders.append(l);
      this.offInputs.push(i);
    }
    this.lambdaKeys = new KeyList($('#lambda-keys'), 'lambda', 0, 1);
    this.etaKeys = new KeyList($('#eta-keys'), 'eta', -100, 100);
    $('#add-lambda-key').addEventListener('click', () => this.lambdaKeys.add([this.nextStep(), 0.5]));
    $('#add-eta-key').addEventListener('click', () => this.etaKeys.add([this.nextStep(), 0]));
    this.step = 0;
    $('#apply-schedule').addEventListener('click', () => session.send([this.edit()]));
  }

  nextStep() { return this.step + 10; }

  /** Shows a session's schedule (summary.schedule, at summary.step). */
  show({ schedule, step }) {
    if (!schedule) return;
    this.step = step ?? 0;
    const editing = this.orders.contains(document.activeElement);
    if (!editing) {
      schedule.apical_off.forEach((v, k) => { if (this.offInputs[k]) this.offInputs[k].value = v === null ? '' : String(v); });
    }
    this.lambdaKeys.set(schedule.lambda_keys);
    this.etaKeys.set(schedule.eta_keys);
  }

  /** The set_apical_schedule edit for what the panel shows. */
  edit() {
    return {
      op: 'set_apical_schedule',
      apical_off: this.offInputs.map((i) => (i.value === '' ? null : Math.max(0, Math.round(Number(i.value))))),
      lambda_keys: this.lambdaKeys.get(),
      eta_keys: this.etaKeys.get(),
    };
  }
}

class KeyList {
  constructor(root, name, min, max) {
    this.root = root; this.name = name; this.min = min; this.max = max;
    this.dirty = false;
  }

  set(keys) {
    if (this.dirty || this.root.contains(document.activeElement)) return;
    this.root.replaceChildren();
    for (const k of keys) this.add(k, false);
  }

  add([step, value], mark = true) {
    const row = document.createElement('div');
    row.className = 'key';
    row.innerHTML = `<label>step <input type="number" class="key-step" min="0" step="1"></label>
      <label>${this.name === 'lambda' ? 'λ' : 'η'} <input type="number" class="key-value" step="0.01" min="${this.min}" max="${this.max}"></label>
      <button class="small remove" title="remove">×</button>`;
    row.querySelector('.key-step').value = String(step);
    row.querySelector('.key-value').value = String(value);
    row.querySelector('.remove').addEventListener('click', () => { row.remove(); this.dirty = true; });
    row.addEventListener('input', () => { this.dirty = true; });
    this.root.append(row);
    if (mark) this.dirty = true;
  }

  get() {
    this.dirty = false;
    return [...this.root.querySelectorAll('.key')]
      .map((r) => [Math.round(Number(r.querySelector('.key-step').value)), Number(r.querySelector('.key-value').value)])
      .sort((a, b) => a[0] - b[0]);
  }
}
