// The Babylon page's chain panel: the sample's root entries, a slider per parameter and a
// "simulated" switch, each edit sent whole to simulation.updateParams (the Builder's live tuning:
// an entry removed takes its chain back to rest, an entry added starts one).
const kParams = ['stiffness', 'gravityPower', 'drag'];

export class ChainPanel {
  /** `entry` is the wearable's models entry (node name -> parameters); it is copied. */
  constructor(entry, onChange) {
    this.entry = structuredClone(entry);
    this.removed = new Map();  // root name -> its entries while the chain is switched off
    this.onChange = onChange;
    this.rootSelect = document.getElementById('root');
    this.simulated = document.getElementById('simulated');
    for (const [name, params] of Object.entries(this.entry)) {
      if (params.isRoot === true) this.rootSelect.add(new Option(name, name));
    }
    this.rootSelect.addEventListener('change', () => this.show());
    this.simulated.addEventListener('change', () => this.setSimulated(this.rootSelect.value, this.simulated.checked));
    for (const key of kParams) {
      document.getElementById(key).addEventListener('input', (event) => this.setParam(this.rootSelect.value, key, Number(event.target.value)));
    }
    this.show();
  }

  show() {
    const root = this.rootSelect.value;
    const params = this.entry[root] ?? this.removed.get(root)?.[root];
    this.simulated.checked = root in this.entry;
    for (const key of kParams) {
      document.getElementById(key).value = params[key];
      document.getElementById(`${key}-value`).textContent = Number(params[key]).toFixed(2);
      document.getElementById(key).disabled = !this.simulated.checked;
    }
  }

  setParam(root, key, value) {
    if (!(root in this.entry)) return;
    this.entry[root] = { ...this.entry[root], [key]: value };
    this.show();
    this.onChange(this.entry);
  }

  /** Off: the root's entry and its members' (nodes named after it) leave the entry. */
  setSimulated(root, on) {
    if (!on && root in this.entry) {
      const own = Object.fromEntries(Object.entries(this.entry).filter(([name]) => name === root || name.startsWith(`${root}_`)));
      for (const name of Object.keys(own)) delete this.entry[name];
      this.removed.set(root, own);
    } else if (on && this.removed.has(root)) {
      Object.assign(this.entry, this.removed.get(root));
      this.removed.delete(root);
    }
    this.show();
    this.onChange(this.entry);
  }
}
