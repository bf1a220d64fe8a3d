"""An outsider's box-only simulator that says so up front: SHAPES = ("box",), so the harness
never calls it on another body. Written with dicts: the state as a dict, the laws as a table
of functions; explicit Euler (every update from the state at the start of the step)."""
import math

SHAPES = ("box",)
INTEGRATOR = "explicit_euler"

NAMES = ("x", "y", "th", "vx", "vy", "om")
NORMAL = {
    "compression": lambda k, c, d, v: k * d + c * max(0.0, -v),
    "linear": lambda k, c, d, v: max(0.0, k * d - c * v),
    "unclamped": lambda k, c, d, v: k * d - c * v,
}


def rates(s, scene):
    """The state's time derivative as a dict."""
    mp, law, on = scene["mass_properties"], scene["contact"], scene["effects"]
    m = mp["mass"]
    f = {"x": 0.0, "y": -m * scene["g"] if "gravity" in on else 0.0, "th": 0.0}
    if "contact" in on:
        cos, sin = math.cos(s["th"]), math.sin(s["th"])
        for px, py in mp["contact_points"]:
            r = {"x": cos * px - sin * py, "y": sin * px + cos * py}
            depth = -(s["y"] + r["y"])
            if depth > 0.0:
                slip, closing = s["vx"] - s["om"] * r["y"], s["vy"] + s["om"] * r["x"]
                fn = NORMAL[law["damping_law"]](law["k"], law["c"], depth, closing)
                ft = -law["mu"] * fn * math.tanh(law["alpha"] * slip) if "friction" in on else 0.0
                f["x"] += ft
                f["y"] += fn
                f["th"] += r["x"] * fn - r["y"] * ft
    return {"x": s["vx"], "y": s["vy"], "th": s["om"],
            "vx": f["x"] / m, "vy": f["y"] / m, "om": f["th"] / mp["inertia"]}


def step(state, scene, dt):
    s = dict(zip(NAMES, map(float, state)))
    d = rates(s, scene)
    return [s[n] + dt * d[n] for n in NAMES]
