"""An outsider's simulator, shaped like a port of a small C engine: module-level work arrays
reused between calls, an index loop over the contact points, semi-implicit Euler. It keeps
state between calls, as such code often does:
- the damper reads the penetration rate by a backward difference against the previous call's
  depth of the same point (not the state's velocity);
- friction is a stick/slip state machine: a sticking point is held to an anchor on the ground
  by a stiff spring, and slips (Coulomb, mu Fn) when that spring would need more than mu Fn.
A step called out of order answers with another state than its run used."""
import math

INTEGRATOR = "semi_implicit_euler"

MAXPT = 8
K_ANCHOR = 2.0e4      # N/m: the stick spring
C_ANCHOR = 40.0       # N s/m: its damper

g_prev_depth = [0.0] * MAXPT    # m: each point's depth at the previous call (0: not touching)
g_anchor = [None] * MAXPT       # m: where each sticking point is held on the ground
g_called = [0]


def step(state, scene, dt):
    x, y, th, vx, vy, om = (float(v) for v in state)
    mp = scene["mass_properties"]
    m, inertia = mp["mass"], mp["inertia"]
    ct = scene["contact"]
    fx_ = ["gravity", "contact", "friction"]
    on = [e in scene["effects"] for e in fx_]
    fx, fy, tq = 0.0, (-m * scene["g"] if on[0] else 0.0), 0.0
    cs, sn = math.cos(th), math.sin(th)
    first = g_called[0] == 0
    g_called[0] += 1
    pts = mp["contact_points"]
    for i in range(len(pts)):
        px, py = pts[i]
        rx, ry = cs * px - sn * py, sn * px + cs * py
        depth = -(y + ry)
        if not on[1] or depth <= 0.0:
            g_prev_depth[i] = 0.0
            g_anchor[i] = None
            continue
        # the penetration rate from the previous call (the state's own on the first touch)
        rate = (depth - g_prev_depth[i]) / dt if (g_prev_depth[i] > 0.0 and not first) else -(vy + om * rx)
        g_prev_depth[i] = depth
        fn = max(0.0, ct["k"] * depth + ct["c"] * rate)
        ft = 0.0
        if on[2]:
            xc = x + rx                       # the point's place along the ground
            vt = vx - om * ry
            if g_anchor[i] is None:
                g_anchor[i] = xc
            ft = -K_ANCHOR * (xc - g_anchor[i]) - C_ANCHOR * vt
            if abs(ft) > ct["mu"] * fn:       # slips: Coulomb, and the anchor follows the point
                ft = math.copysign(ct["mu"] * fn, ft)
                g_anchor[i] = xc + ft / K_ANCHOR
        fx += ft
        fy += fn
        tq += rx * fn - ry * ft
    vx += dt * fx / m
    vy += dt * fy / m
    om += dt * tq / inertia if mp["rotates"] else 0.0
    return [x + dt * vx, y + dt * vy, th + dt * om, vx, vy, om]


def simulate(scene):
    import numpy as np
    z = list(scene["state0"])
    out = [z]
    for _ in range(scene["steps"]):
        z = step(z, scene, scene["dt"])
        out.append(z)
    return np.array(out)
