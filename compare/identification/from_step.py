"""Identification from a step function: call it from the designed states, then fit every family."""
from __future__ import annotations

import time

import numpy as np

from custom_sim import Scene

from . import forward, roundoff
from .calls import StepCalls
from .families import FAMILIES, Family, scene_family
from .fit import Fit, choose, rounded, weights, worst
from .geometry import Geometry
from .integrators import evaluated_at
from .model import Law
from .observed import Rows, TorqueRows, fit_effect, fit_torque, model_of, torque_model
from .onset import OnsetSearch
from .probes import (DEPTH_SHARE_OF_MARGIN, FRICTION_DEPTHS, NORMAL_DEPTHS, Probes, Scales, contact_states, flight,
                     main_point, pairs, state)
from .replay import keeps_state
from .result import (body_entry, effect_entry, gravity_entry, integrator_entry, not_exercised, settle_body,
                     unread_entry)
from .roundoff import inertias, rate_bound
from .stepping import contact_shown, decide, integrator_tests, rates, restart_states

EFFECT_OF = {"normal": "contact", "friction": "friction", "rolling": "rolling_friction"}
# The probes press the main point until its force at rest is at least this share of the weight
# (the law is read where it carries the body, not where its first ulps show).
FORCE_OF_WEIGHT = 0.5
DEPTH_DOUBLINGS = 40
DEPTH_BISECTIONS = 60
# The force at each depth found is this close to its multiple of m g (the depths need not be exact).
DEPTH_FORCE_RTOL = 0.05
# A fit whose probes saw no load above this many times its round-off bound is no finding: every
# family fits noise (a spring of 1e-11 N/m "reproduces" forces of 1e-12 N).
READABLE = 100.0


def scene_law(scene: Scene, scene_d: dict, geometry: Geometry | None = None) -> Law:
    """The scene's own law: the effects it lists, with the scene's families and parameters."""
    mp = scene_d["mass_properties"]
    geometry = geometry or Geometry.of_scene(scene_d)

    def part(effect):
        return scene_family(scene, effect) if scene.has(EFFECT_OF[effect]) else None
    return Law(g=scene.g if scene.has("gravity") else 0.0, mass=mp["mass"], inertia=mp["inertia"],
               geometry=geometry, normal=part("normal"), friction=part("friction"), rolling=part("rolling"))


def _gravity(law: Law, F: Probes) -> tuple[float, float, float, float]:
    """(g m/s^2, largest residual m/s^2, relative, the scene's g relative) from the flight
    steps: a = (0, -g, 0) to round-off; g rounded to the digits the steps carry (fit.rounded)."""
    a = rates(F)
    M = inertias(law)
    b = rate_bound(law.with_(normal=None), "semi_implicit_euler", F.Z0, F.Z1, F.H) / M
    w = weights(b[:, 1])
    g = float(np.sum(-a[:, 1] * w) / np.sum(w))
    r, rel = worst(a - np.array([0.0, -g, 0.0]), b)
    (g,) = rounded((g,), (float(np.min(b[:, 1])),), lambda p: worst(a - np.array([0.0, -p[0], 0.0]), b)[1], rel)
    r, rel = worst(a - np.array([0.0, -g, 0.0]), b)
    return g, r, rel, worst(a - np.array([0.0, -law.g, 0.0]), b)[1]


class StepIdentification:
    """One scene's identification from a step function (see the module)."""

    def __init__(self, simulator, scene: Scene):
        self.scene = scene
        self.calls = StepCalls(simulator, scene)
        self.sd = self.calls.scene_d
        self.geometry_scene = Geometry.of_scene(self.sd)
        self.scales = Scales.of(self.sd, self.geometry_scene)
        self.law_scene = scene_law(scene, self.sd, self.geometry_scene)

    def run(self) -> dict:
        return roundoff.in_own_context(self._run)

    def _run(self) -> dict:
        start = time.perf_counter()
        scene, law_s = self.scene, self.law_scene
        out = {"scene": scene.name, "from": "step"}
        F = flight(self.geometry_scene, self.scales)
        F.Z1 = self.calls.many(F.Z0, F.H, "flight")
        # float32 arithmetic behind float64 returns: every bound below in single precision
        out["precision"] = "float32" if roundoff.is_float32(F.Z0, F.Z1) else "float64"
        roundoff.set_single_precision(out["precision"] == "float32")
        g, g_res, g_rel, g_scene = _gravity(law_s, F)
        out["gravity"] = gravity_entry(g, g_res, g_rel, g_scene)
        g_use = g if g_rel <= 1.0 else law_s.g
        contact = scene.has("contact")
        P2 = restart = quarter = None
        if contact:
            P2 = pairs(self.geometry_scene, self.scales)
            P2.Z1 = self.calls.many(P2.Z0, P2.H, "contact at dt and dt/2")
        # purity before any law: the probes so far (flight, contact) replayed out of order
        made = [F] if P2 is None else [F, P2]
        with self.calls.session():
            stateful = keeps_state(self.calls, np.vstack([p.Z0 for p in made]),
                                   np.concatenate([np.broadcast_to(p.H, (len(p),)) for p in made]),
                                   np.vstack([p.Z1 for p in made]), "flight and contact")
        if stateful:
            return self._from_run(stateful)
        if contact:
            Zr, Hr = restart_states(P2)
            restart = ((Zr, Hr), self.calls.many(Zr, Hr, "implicit Euler restart"))
            quarter = self.calls.many(P2.Z0[0::2], 0.25 * P2.H[0::2], "contact at dt/4")
        law0 = law_s.with_(g=g_use)
        tests = integrator_tests(law0, F, P2, restart, quarter)
        name, closest, rel, why = decide(tests)
        if contact and not contact_shown(law0, F, P2):
            name, why = None, "the contact probes show no force (the step never touches the ground here)"
        used = closest if name is None else ("rk4" if name == "rk4?" else name)
        if name is None and tests.get("reads_at_end") and not tests.get("reads_at_start"):
            used = "implicit_euler"       # the force at the end of the step, whatever moves the positions
        elif name is None and (tests.get("reads_at_start") or closest != "rk4"):
            used = "explicit_euler"       # the force at the start: m (v1 - v0) / h is the force at z0
        if not contact:
            out["integrator"] = integrator_entry(name if name != "rk4?" else "rk4", closest, rel, tests, why, scene)
            for effect in ("normal", "friction", "rolling"):
                out[effect] = not_exercised(f"the scene does not list {EFFECT_OF[effect]}")
            out["body"] = body_entry(law_s, None, None, [], scene, rotates=self.geometry_scene.rotates)
            return self._finish(out, start)

        search = OnsetSearch(self.calls, self.geometry_scene, self.scales, g_use, used)
        found, missing, turn = search.points()
        geometry = self._geometry(found, turn).with_onset(search.onset or 0.0)
        law = law0.with_(geometry=geometry)
        self.scales = self._working_depth(law, used)
        P = contact_states(geometry, self.scales, scene.has("friction"), scene.has("rolling_friction"))
        P.Z1 = self.calls.many(P.Z0, P.H, "contact")
        if used == "rk4":
            fits = self._fit_rk4(law, P)
        else:
            fits = self._fit_euler(law, P, used)
        unread = self._unread(law, P)
        if name == "rk4?":
            name = "rk4" if fits["rk4_relative"] <= 1.0 else None
            rel = max(rel, fits["rk4_relative"])
            if name:
                tests["depends_on_dt"] = False   # a law of the state, stepped by RK4, reproduces it
            why = "flight and the contact probes stepped by RK4 under the law found" if name else \
                "none: beta = 1/2 (RK4's), but RK4 under the closest laws does not reproduce the contact probes"
        out["integrator"] = integrator_entry(name, closest if name is None else name, rel, tests, why, scene)
        for effect in ("normal", "friction", "rolling"):
            if not scene.has(EFFECT_OF[effect]):
                out[effect] = not_exercised(f"the scene does not list {EFFECT_OF[effect]}")
            elif effect in unread:
                out[effect] = unread_entry(effect, *unread[effect])
            else:
                out[effect] = effect_entry(effect, *fits[effect], fits["scene_" + effect])
        out["body"] = body_entry(law_s, fits["body"], found, missing, scene, turn=turn,
                                 rotates=self.geometry_scene.rotates)
        # Euler: the torque rests on the forces read off the step and the rolling law fitted beside
        # the inertia; RK4: on every law found, stepped here
        settle_body(out, ("normal", "friction", "rolling") if used == "rk4" else ("rolling",))
        if search.onset is not None:   # the force begins above (or below) the contact points
            out["normal"]["onset"] = search.onset
        return self._finish(out, start)

    def _from_run(self, why: str) -> dict:
        """A step that keeps state: identified by regression over its own sequential run from the
        scene's start (the --whole route), where that run allows."""
        from .whole_run import identify_run
        run = self.calls.simulator.run(self.scene)
        out = identify_run(run.states, self.scene, run.rounding, "run")
        out.update(keeps_state=True, keeps_state_why=why, calls=self.calls.count)
        return out

    def _working_depth(self, law: Law, integrator: str) -> Scales:
        """The scales with the probe depths where the step's normal force is of the order of m g,
        at least the scene's. The scene's resting compression where the main point at rest
        carries FORCE_OF_WEIGHT of m g or more there (the depths are then its multiples, as
        always); else, for each multiple s of the probe depth, the depth (from the onset) where
        the force at rest is s m g, by doubling and bisection (never past an eighth of the gap to
        the next point, nor past a depth where the step's state stops being finite)."""
        import dataclasses

        from ..usersim.errors import UserCodeError
        i, theta, gap = main_point(law.geometry)
        weight = law.mass * max(law.g, 0.0)
        limit = DEPTH_SHARE_OF_MARGIN * gap
        if weight <= 0.0:
            return self.scales
        h = self.scales.dt

        def force(d):
            z0 = state(law.geometry, i, theta, d)
            try:
                z1 = self.calls.one(z0, h, "the depth where the force is m g")
            except UserCodeError:
                return np.inf
            return law.mass * ((z1[4] - z0[4]) / h + law.g)

        d0 = min(self.scales.depth, limit)
        f0 = force(d0)
        if f0 >= FORCE_OF_WEIGHT * weight:   # the scene's depth already carries the weight: at least that deep
            return self.scales
        depths = {}
        for share in sorted({*NORMAL_DEPTHS, *FRICTION_DEPTHS}):
            want = share * weight
            lo, hi = 0.0, d0
            while force(hi) < want and hi < limit and len(depths) < 1 + DEPTH_DOUBLINGS and hi < 1e6 * d0:
                lo, hi = hi, 2.0 * hi
            hi = min(hi, limit)
            for _ in range(DEPTH_BISECTIONS):
                mid = 0.5 * (lo + hi)
                f = force(mid)
                if abs(f - want) <= DEPTH_FORCE_RTOL * want:
                    lo = hi = mid
                    break
                lo, hi = (mid, hi) if f < want else (lo, mid)
            depths[share] = max(0.5 * (lo + hi), share * d0)
        return dataclasses.replace(self.scales, depth=depths[1.0], depths=depths, rest=d0)

    def _unread(self, law: Law, P: Probes) -> dict:
        """{effect: (largest force seen N, its bound N)} for each effect whose probes saw no force
        above READABLE x round-off: a fit to those is no finding. The normal force on the normal
        probes; friction and rolling on the load they scale with, and their own force."""
        r = self._readings(law, P, "explicit_euler")
        B = rate_bound(law, "explicit_euler", P.Z0, P.Z1, P.H)
        out = {}
        for effect, kinds, force, ch in (("normal", ("normal",), r["fn"], 1),
                                         ("friction", ("normal", "friction", "rolling"), r["ft"], 0),
                                         ("rolling", ("rolling",), r["a"][:, 2] * inertias(law)[2], 2)):
            rows = np.isin(P.kind, kinds)
            if not rows.any():
                continue
            load = np.max(np.abs(r["fn"][rows]) / np.maximum(B[rows, 1], np.finfo(float).tiny))
            if load <= READABLE:
                out[effect] = (float(np.max(np.abs(force[rows]))), float(np.max(B[rows, ch])))
        return out

    def _finish(self, out: dict, start: float) -> dict:
        from .result import matches
        out["keeps_state"] = False
        out["matches_scene"] = matches(out, self.scene)
        if out.get("normal", {}).get("onset") is not None:   # the scene's force begins at its points
            out["matches_scene"]["normal"] = False
        out["calls"] = self.calls.count
        out["seconds"] = time.perf_counter() - start
        return out

    def _geometry(self, found, turn) -> Geometry:
        """The scene's geometry with every point found put where the step has it."""
        geom = self.geometry_scene
        pts = geom.points.copy()
        for f in found:
            lx, ly = f.point
            # a point found where the scene has it, to round-off, keeps the scene's exact numbers
            # (a slip of exactly zero stays zero for a step that reads them: the sign law's edge)
            same = np.abs(np.array([geom.points[f.index, 0] if lx is None else lx, ly]) - geom.points[f.index])
            if np.all(same <= np.where(np.isfinite(f.uncertainty), f.uncertainty, 0.0)):
                continue
            if lx is not None:
                pts[f.index, 0] = lx
            pts[f.index, 1] = ly
        rotate = geom.rotate if turn is None else turn
        return Geometry(pts, rotate, geom.rotates)

    # -- the Euler steps: forces read at a known state ------------------------------------

    def _readings(self, law: Law, P: Probes, integrator: str):
        Ze = evaluated_at(integrator, P.Z0, P.Z1)
        a = rates(P)
        rx, ry = law.geometry.arms(Ze[:, 2])
        idx = np.arange(len(P))
        rx, ry = rx[idx, P.point], ry[idx, P.point]
        d = law.geometry.onset - (Ze[:, 1] + ry)
        vn = Ze[:, 4] + Ze[:, 5] * rx
        slip = Ze[:, 3] - Ze[:, 5] * ry
        fn = law.mass * (a[:, 1] + law.g)
        ft = law.mass * a[:, 0]
        return dict(a=a, rx=rx, ry=ry, d=d, vn=vn, slip=slip, om=Ze[:, 5], fn=fn, ft=ft)

    def _fit_euler(self, law: Law, P: Probes, integrator: str) -> dict:
        r = self._readings(law, P, integrator)
        B = rate_bound(law, integrator, P.Z0, P.Z1, P.H)
        one = np.ones((len(P), 1), dtype=bool)
        col = lambda v: v[:, None]   # noqa: E731 - one point per probe

        def bound_of(rows_mask, channel):
            def f(fam: Family, p):
                return rate_bound(law.with_(**{fam.effect: (fam, p)}), integrator, P.Z0[rows_mask], P.Z1[rows_mask],
                                  P.H[rows_mask])[:, channel]
            return f

        out = {}
        nm = P.kind == "normal"
        rows = Rows(r["fn"][nm], B[nm, 1], one[nm], col(r["d"])[nm], col(r["vn"])[nm])
        fits = fit_effect(FAMILIES["normal"], rows, bound_of(nm, 1))
        out["normal"] = choose(fits, self.scene.contact.damping_law) + (fits,)
        out["scene_normal"] = self._scene_fit(law.normal, rows)
        # friction: the step's own normal force carries its bound into the friction's
        fr = np.isin(P.kind, ("normal", "friction", "rolling"))
        mu = max(self.scene.contact.mu, 1.0)
        rows = Rows(r["ft"][fr], B[fr, 0] + mu * B[fr, 1], one[fr], col(r["fn"])[fr], col(r["slip"])[fr])
        if law.friction is not None:
            fits = fit_effect(FAMILIES["friction"], rows, bound_of(fr, 0))
            out["friction"] = choose(fits, self.scene.contact.friction_law) + (fits,)
            out["scene_friction"] = self._scene_fit(law.friction, rows)
        # the torque: inertia, the arm of a point that does not turn, and the rolling law
        out.update(self._fit_torque(law, P, r, B))
        return out

    def _scene_fit(self, part, rows: Rows) -> Fit | None:
        if part is None:
            return None
        fam, p = part
        res, rel = worst(rows.target - model_of(fam, rows, p), rows.bound)
        return Fit(fam, p, res, rel)

    def _fit_torque(self, law: Law, P: Probes, r: dict, B: np.ndarray) -> dict:
        geom = law.geometry
        if not geom.rotates:   # the point mass: the step must not turn it
            res, rel = worst(r["a"][:, 2], B[:, 2])
            return {"body": {"inertia": 0.0, "lx": float("nan"), "residual": res, "relative": rel,
                             "scene_relative": rel},
                    "rolling": (None, [], None, []), "scene_rolling": None}
        rows_all = TorqueRows(r["a"][:, 2], r["rx"][:, None], r["ry"][:, None], r["fn"][:, None], r["ft"][:, None],
                              r["om"], np.ones((len(P), 1), dtype=bool),
                              B[:, 2] + np.abs(r["rx"]) * B[:, 1] + np.abs(r["ry"]) * B[:, 0] + 1e-3 * B[:, 1],
                              free_arm=not geom.rotate)
        roll = P.kind == "rolling"
        fams = FAMILIES["rolling"] if law.rolling is not None else (None,)
        fits, bodies = [], []
        moving = np.abs(rows_all.alpha) > 0
        # what the torques resolve of the inertia: the change that moves some row by its bound
        i_res = float(np.min(rows_all.bound[moving] / np.abs(rows_all.alpha[moving]))) if moving.any() else None
        for fam in fams:
            resid, inertia, lx, p = fit_torque(rows_all, fam, law.inertia)
            br, brel = worst(resid[~roll], rows_all.bound[~roll])
            (inertia,) = rounded((inertia,), (i_res,), lambda q: worst(
                self._torque_at(rows_all, fam, p, q[0], lx)[~roll], rows_all.bound[~roll])[1], brel)
            resid = self._torque_at(rows_all, fam, p, inertia, lx)
            rr, rrel = worst(resid[roll], rows_all.bound[roll])
            br, brel = worst(resid[~roll], rows_all.bound[~roll])
            if fam is not None:
                fits.append(Fit(fam, p, rr, rrel, {"inertia": inertia, "lx": lx}))
            bodies.append({"inertia": inertia, "lx": lx, "residual": br, "relative": brel, "family": fam})
        out = {}
        if law.rolling is not None:
            named, also, closest = choose(fits, self.scene.contact.roll_law)
            out["rolling"] = (named, also, closest, fits)
            pick = named or closest
            body = bodies[fits.index(pick)]
            fam_s, p_s = law.rolling
            resid = self._torque_at(rows_all, fam_s, p_s, body["inertia"], body["lx"])
            out["scene_rolling"] = Fit(fam_s, p_s, *worst(resid[roll], rows_all.bound[roll]))
            rolling_part = (pick.family, pick.params)
        else:
            body = bodies[0]
            out["scene_rolling"] = None
            rolling_part = None
        # the scene's inertia and arm, with the rolling law found
        lx_s = float(self.geometry_scene.points[0, 0]) if not geom.rotate else float("nan")
        fam_r, p_r = rolling_part if rolling_part else (None, ())
        resid = self._torque_at(rows_all, fam_r, p_r, law.inertia, lx_s)
        body["scene_relative"] = worst(resid[~roll], rows_all.bound[~roll])[1]
        out["body"] = body
        return out

    @staticmethod
    def _torque_at(rows: TorqueRows, fam, p, inertia, lx) -> np.ndarray:
        """I alpha - the torque of the law (N m) per row."""
        return inertia * rows.alpha - torque_model(rows, fam, p, lx)

    # -- RK4: the law stepped here, started from the Euler reading -----------------------

    def _fit_rk4(self, law: Law, P: Probes) -> dict:
        guess = self._fit_euler(law, P, "explicit_euler")
        rows_n = np.flatnonzero(P.kind == "normal")
        rows_f = np.flatnonzero(P.kind != "normal")
        out = {}
        # 1. the normal law on the normal probes' vertical channel (no slip, no spin: nothing else acts)
        fits = []
        for fit in guess["normal"][3]:
            trial = forward.fit(law.with_(normal=(fit.family, fit.params)), forward.family_slots(
                law.with_(normal=(fit.family, fit.params)), "normal"), "rk4", P.Z0, P.Z1, P.H, rows_n, [1])
            st = forward.compare(trial, "rk4", P.Z0, P.Z1, P.H)
            fits.append(Fit(fit.family, trial.normal[1], *st.worst(rows_n, [1])))
        out["normal"] = choose(fits, self.scene.contact.damping_law) + (fits,)
        best_n = out["normal"][0] or out["normal"][2]
        law = law.with_(normal=(best_n.family, best_n.params))
        st = forward.compare(law.with_(normal=self.law_scene.normal), "rk4", P.Z0, P.Z1, P.H)
        out["scene_normal"] = Fit(self.law_scene.normal[0], self.law_scene.normal[1], *st.worst(rows_n, [1]))
        # 2. friction, rolling and the inertia together on the other probes (spin couples them)
        f_fams = [(f.family, f.params) for f in guess["friction"][3]] if law.friction is not None else [None]
        r_fams = [(f.family, f.params) for f in guess["rolling"][3]] if law.rolling is not None else [None]
        inertia0 = guess["body"]["inertia"] if np.isfinite(guess["body"]["inertia"]) else law.inertia
        lx0 = guess["body"]["lx"]
        roll_rows = np.flatnonzero(P.kind == "rolling")
        fric_rows = np.flatnonzero(np.isin(P.kind, ("friction", "rolling")))
        body_rows = np.flatnonzero(np.isin(P.kind, ("friction", "torque")))
        # the arm of a point that does not turn (the circle's) stays the scene's unless that fails:
        # a fitted l_x of 1e-28 m puts a torque on every stage, which the sign laws' edge at zero
        # slip turns into a full friction force the step never had
        arms = [False, True] if not law.geometry.rotate and law.geometry.rotates and np.isfinite(lx0) else [False]
        def stepped(fpart, rpart, free_arm):
            trial = law.with_(friction=fpart, rolling=rpart, inertia=inertia0)
            slots = forward.family_slots(trial, "friction") + forward.family_slots(trial, "rolling")
            if law.geometry.rotates:
                slots.append(("inertia", 0))
            if free_arm:
                trial = forward.build(trial, [("lx", 0)], [lx0])
                slots.append(("lx", 0))
            trial = forward.fit(trial, slots, "rk4", P.Z0, P.Z1, P.H, rows_f, [0, 1, 2])
            return trial, forward.compare(trial, "rk4", P.Z0, P.Z1, P.H)

        def score(combo, rows, ch):
            return combo[1].worst(rows, [ch])[1]
        # every friction family beside the rolling law the Euler reading liked best, then every
        # rolling family beside the friction law that fitted best (not all pairs: spin couples
        # them only weakly, so each is found beside a near-right other)
        r_guess = min(range(len(r_fams)), key=lambda j: guess["rolling"][3][j].relative) if r_fams != [None] else 0
        for free_arm in arms:
            combos = [stepped(fpart, r_fams[r_guess], free_arm) for fpart in f_fams]
            f_best = min(range(len(f_fams)), key=lambda j: score(combos[j], fric_rows, 0))
            combos += [stepped(f_fams[f_best], rpart, free_arm) for j, rpart in enumerate(r_fams) if j != r_guess]
            chosen = self._rk4_choose(combos, fric_rows, roll_rows, body_rows, law)
            if free_arm and max(_rel(chosen.get(e)) for e in ("friction", "rolling")) >= max(
                    _rel(out.get(e)) for e in ("friction", "rolling")) and chosen["body"]["relative"] >= \
                    out["body"]["relative"]:
                break
            out.update(chosen)
            if all(_rel(out.get(e)) <= 1.0 for e in ("friction", "rolling")) and out["body"]["relative"] <= 1.0:
                break
        final = out.pop("law")
        st = forward.compare(final, "rk4", P.Z0, P.Z1, P.H)
        everything = np.arange(len(P))
        out["rk4_relative"] = st.worst(everything, [0, 1, 2])[1]
        # the scene's friction, rolling and inertia, stepped with the normal law found
        scene_all = final.with_(friction=self.law_scene.friction, rolling=self.law_scene.rolling,
                                inertia=self.law_scene.inertia, geometry=law.geometry)
        st_s = forward.compare(scene_all, "rk4", P.Z0, P.Z1, P.H)
        for effect, rows_e, ch in (("friction", fric_rows, 0), ("rolling", roll_rows, 2)):
            part = getattr(self.law_scene, effect)
            out["scene_" + effect] = None if part is None else Fit(part[0], part[1], *st_s.worst(rows_e, [ch]))
        body = out["body"]
        body["scene_relative"] = st_s.worst(body_rows, [2])[1] if law.geometry.rotates else body["relative"]
        return out

    def _rk4_choose(self, combos, fric_rows, roll_rows, body_rows, law: Law) -> dict:
        """Each effect's family from the combinations fitted (friction x rolling), by choose();
        the law is the combination of the families named (or closest)."""
        scored = [(trial, st.worst(fric_rows, [0]), st.worst(roll_rows, [2]), st.worst(body_rows, [2]))
                  for trial, st in combos]
        out = {}
        picks = {}
        for effect, k, field in (("friction", 1, "friction_law"), ("rolling", 2, "roll_law")):
            if getattr(law, effect) is None:
                out[effect] = (None, [], None, [])
                continue
            per = {}
            for t in scored:
                fam = getattr(t[0], effect)[0]
                if fam.name not in per or t[k][1] < per[fam.name][1].relative:
                    per[fam.name] = (t, Fit(fam, getattr(t[0], effect)[1], t[k][0], t[k][1]))
            fits = [per[f.name][1] for f in FAMILIES[effect] if f.name in per]
            named, also, closest = choose(fits, getattr(self.scene.contact, field))
            out[effect] = (named, also, closest, fits)
            picks[effect] = (named or closest).family
        best = [t for t in scored if all(getattr(t[0], e)[0] is fam for e, fam in picks.items())]
        trial, _, _, b = min(best or scored, key=lambda t: max(t[1][1], t[2][1], t[3][1]))
        for effect in picks:   # the parameters of the combination kept
            named, also, closest, fits = out[effect]
            part = getattr(trial, effect)
            k = 1 if effect == "friction" else 2
            mine = next(t for t in scored if t[0] is trial)
            fit = Fit(part[0], part[1], mine[k][0], mine[k][1])
            out[effect] = (fit if named is not None and fit.fits else named, also, closest if named is None else fit,
                           fits)
        lx = float(trial.geometry.points[0, 0]) if not law.geometry.rotate else float("nan")
        out["body"] = {"inertia": trial.inertia if law.geometry.rotates else 0.0, "lx": lx,
                       "residual": b[0], "relative": b[1]}
        out["law"] = trial
        return out


def _rel(entry) -> float:
    """The relative residual of an effect's (named, also, closest, fits), 0 when not fitted."""
    if not entry or (entry[0] is None and entry[2] is None):
        return 0.0
    return (entry[0] or entry[2]).relative


def identify_step(simulator, scene: Scene) -> dict:
    """The identification of one scene from a step function (compare.usersim.StepFunction)."""
    return StepIdentification(simulator, scene).run()
