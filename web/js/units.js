// units.js - dimensionless <-> physical, from the daemon's PARAMS scale:
// x * length_m metres, F * K_m * length_m newtons, tau / omega_n seconds,
// omega * omega_n / 2 pi Hz mesh frequency (lcmtypes/PROTOCOL.md).

export const TWO_PI = 2 * Math.PI;

// The physical kind of each quantity or parameter that has one.
const KIND = {
  x_n: "length", min_x_n: "length", max_x_n: "length", b: "length", b_j: "length", e_m: "length",
  dx_n: "velocity", velocity: "velocity",
  F: "force", f_m: "force", f_e: "force",
  omega: "frequency",
};

const LABEL = {
  length: ["b_c", "µm"], velocity: ["b_c ω_n", "m/s"], force: ["K_m b_c", "N"], frequency: ["ω_n", "Hz"],
};

export class Units {
  constructor() { this.physical = false; this.scale = null; }
  setScale(p) { this.scale = { wn: p.omega_n_rad_s, L: p.length_m, K: p.mesh_stiffness_N_m }; }
  usable() { return this.physical && this.scale && this.scale.wn > 0 && this.scale.L > 0; }
  factor(name) {
    const k = KIND[name];
    if (!k || !this.usable()) return 1;
    const { wn, L, K } = this.scale;
    return { length: L * 1e6, velocity: L * wn, force: K * L, frequency: wn / TWO_PI }[k];
  }
  // value in the displayed unit, and back
  show(name, v) { return v * this.factor(name); }
  parse(name, v) { return v / this.factor(name); }
  unit(name, fallback = "1") {
    const k = KIND[name];
    if (!k) return fallback;
    return LABEL[k][this.usable() ? 1 : 0];
  }
}
