"""An outsider's simulator in yet another style: the plane as complex numbers. Positions,
arms and velocities are complex (x + i y), a rotation is a multiplication by exp(i theta), the
cross product r x F is Im(conj(r) F). The force law is built from small closures made once per
scene and cached by the scene's id. Semi-implicit Euler."""
import cmath
import math

_LAWS = {}


def _law(scene):
    """(gravity, contact points, force(depth, v_point) -> complex) for the scene, made once."""
    key = id(scene)
    if key in _LAWS:
        return _LAWS[key]
    mp, ct, on = scene["mass_properties"], scene["contact"], set(scene["effects"])
    weight = -1j * mp["mass"] * scene["g"] if "gravity" in on else 0j
    points = [complex(px, py) for px, py in mp["contact_points"]] if "contact" in on else []

    def normal(depth, vn):
        if ct["damping_law"] == "compression":
            return ct["k"] * depth + ct["c"] * max(0.0, -vn)
        return max(0.0, ct["k"] * depth - ct["c"] * vn)

    def force(depth, v):
        fn = normal(depth, v.imag)
        ft = -ct["mu"] * fn * math.tanh(ct["alpha"] * v.real) if "friction" in on else 0.0
        return complex(ft, fn)

    _LAWS[key] = (weight, points, force)
    return _LAWS[key]


def step(state, scene, dt):
    x, y, theta, vx, vy, om = (float(s) for s in state)
    mp = scene["mass_properties"]
    weight, points, force = _law(scene)
    turn = cmath.exp(1j * theta) if mp["points_rotate"] else 1.0
    com, vel = complex(x, y), complex(vx, vy)
    total, torque = weight, 0.0
    for p in points:
        r = turn * p
        depth = -(com + r).imag
        if depth <= 0.0:
            continue
        v_point = vel + 1j * om * r          # v + omega x r
        f = force(depth, v_point)
        total += f
        torque += (r.conjugate() * f).imag   # r x F
    vel += dt * total / mp["mass"]
    if mp["rotates"]:
        om += dt * torque / mp["inertia"]
    com += dt * vel
    theta += dt * om
    return [com.real, com.imag, theta, vel.real, vel.imag, om]
