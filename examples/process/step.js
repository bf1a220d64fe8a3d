// The seed's Algorithms 1-4 in JavaScript (node), spoken to over stdin/stdout: examples/seed_sim.py as a process.
//
//     python -m compare run --sim-process "node examples/process/step.js"
//
// The harness writes `scene {JSON}` (the dict `python -m compare scene SCENE --json` prints, on
// one line); this program answers `ready scene` (it steps with the scene's integrator) or
// `skip REASON`. Then each `step DT X Y THETA VX VY OMEGA` line is answered with the state one
// step DT later. A JavaScript number is a double; String(v) is the shortest text that reads back
// to it (at most 17 significant digits). See docs/process-protocol.md.
"use strict";

const fs = require("fs");

const WRITTEN = ["semi_implicit_euler", "explicit_euler", "rk4"];
let scene = null;

function accelerations(z) {
  // (ax, ay, angular acceleration) at z: gravity, then each contact point (Algorithm 2)
  const [, y, theta, vx, vy, om] = z;
  const mp = scene.mass_properties, ct = scene.contact, on = scene.effects;
  const m = mp.mass;
  let fx = 0.0, fy = 0.0, tau = 0.0;
  if (on.includes("gravity")) fy -= m * scene.g;                 // F <- [0, -m g]
  if (on.includes("contact")) {
    const c = mp.points_rotate ? Math.cos(theta) : 1.0, s = mp.points_rotate ? Math.sin(theta) : 0.0;
    for (const [lx, ly] of mp.contact_points) {
      const rx = c * lx - s * ly, ry = s * lx + c * ly;          // r_i <- R(theta) c_i^local
      const d = -(y + ry);                                       // depth below the ground y = 0
      if (d <= 0.0) continue;                                    // no force in the air
      const vcx = vx - om * ry, vcy = vy + om * rx;              // v_i <- v + omega [-r_y, r_x]
      let fn;
      if (ct.damping_law === "compression") {
        fn = ct.k * d + ct.c * (-vcy > 0.0 ? -vcy : 0.0);        // Algorithm 1, line 4
      } else {
        fn = ct.k * d - ct.c * vcy;                              // Kelvin-Voigt, never pulls
        if (!(fn > 0.0)) fn = 0.0;
      }
      const ft = on.includes("friction") ? -ct.mu * fn * Math.tanh(ct.alpha * vcx) : 0.0;
      fx += ft;
      fy += fn;
      tau += rx * fn - ry * ft;                                  // tau <- tau + r_i x F_i
      if (on.includes("rolling_friction")) {                     // Algorithm 4, line 9
        tau -= ct.mu_roll * fn * Math.tanh(ct.roll_sharpness * om);
      }
    }
  }
  return [fx / m, fy / m, mp.rotates ? tau / mp.inertia : 0.0];
}

function derivative(z) {
  const [ax, ay, aw] = accelerations(z);
  return [z[3], z[4], z[5], ax, ay, aw];
}

function step(z, dt) {
  const method = scene.integrator;
  if (method === "semi_implicit_euler") {                        // v <- v + a dt, then p <- p + v dt
    const [ax, ay, aw] = accelerations(z);
    const vx = z[3] + dt * ax, vy = z[4] + dt * ay, om = z[5] + dt * aw;
    return [z[0] + dt * vx, z[1] + dt * vy, z[2] + dt * om, vx, vy, om];
  }
  if (method === "explicit_euler") {                             // p <- p + v dt with the old v
    const d = derivative(z);
    return z.map((v, i) => v + dt * d[i]);
  }
  const h = 0.5 * dt;                                            // rk4
  const k1 = derivative(z);
  const k2 = derivative(z.map((v, i) => v + h * k1[i]));
  const k3 = derivative(z.map((v, i) => v + h * k2[i]));
  const k4 = derivative(z.map((v, i) => v + dt * k3[i]));
  return z.map((v, i) => v + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
}

function ready(s) {
  const on = s.effects, ct = s.contact;
  if (!WRITTEN.includes(s.integrator)) return `skip integrator ${s.integrator} is not written in this example`;
  if (on.includes("friction") && ct.friction_law !== "tanh") return `skip friction law ${ct.friction_law} is not written in this example (tanh only)`;
  if (on.includes("rolling_friction") && ct.roll_law !== "tanh") return `skip rolling law ${ct.roll_law} is not written in this example (tanh only)`;
  if (ct.damping_law !== "compression" && ct.damping_law !== "linear") return `skip damping law ${ct.damping_law} is not written in this example`;
  return "ready scene";
}

function answer(line) {
  if (line.startsWith("step ")) {
    const numbers = line.slice(5).trim().split(/\s+/).map(Number);
    return step(numbers.slice(1, 7), numbers[0]).map(String).join(" ");
  }
  if (line.startsWith("scene ")) {
    scene = JSON.parse(line.slice(6));
    return ready(scene);
  }
  process.stderr.write(`step.js: expected a \`scene\` or \`step\` line, got: ${line}\n`);
  process.exit(2);
}

// One line in, one line out, written at once (the harness waits for each answer). Reading
// fd 0 synchronously keeps the round trip short (no event loop turn per line).
const buffer = Buffer.alloc(1 << 16);
let pending = "";
for (;;) {
  let n;
  try {
    n = fs.readSync(0, buffer, 0, buffer.length, null);
  } catch (err) {
    if (err.code === "EAGAIN") continue;
    if (err.code === "EOF") break;
    throw err;
  }
  if (n === 0) break;                                            // stdin closed: the session is over
  pending += buffer.toString("utf8", 0, n);
  let end;
  let out = "";
  while ((end = pending.indexOf("\n")) >= 0) {
    out += answer(pending.slice(0, end)) + "\n";
    pending = pending.slice(end + 1);
  }
  if (out) fs.writeSync(1, out);
}
