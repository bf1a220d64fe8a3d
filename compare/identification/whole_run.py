"""Identification from a run's states (--whole, --trajectories): regression over the steps it visited."""
from __future__ import annotations

import time

import numpy as np

from custom_sim import Scene

from . import forward, roundoff
from .families import FAMILIES
from .fit import LSQ_MAX_EVALUATIONS, SCOUT_EVALUATIONS, Fit, choose, weights, worst
from .from_step import EFFECT_OF, scene_law
from .geometry import Geometry
from .integrators import POSITION_SHARE, evaluated_at, position_residual
from .model import Law, contacts
from .result import body_entry, effect_entry, settle_body, gravity_entry, integrator_entry, matches, not_exercised
from .roundoff import inertias, position_bound, rate_bound
from .stepping import beta_words, position_share
from ..usersim.scene_dict import scene_dict

# At most this many steps enter a least-squares fit (evenly spread over the steps where the
# effect acts, plus the ones where the scene's law is largest); every step is checked after.
FIT_ROWS = 3000
# A run of steps is flight when its vertical velocity spans at least this many steps of its
# constant acceleration (a ballistic arc); a body held by a force has none.
FLIGHT_SPAN_STEPS = 10
# Starting points of a sharpness (alpha, roll_sharpness) around the scene's, for a fit over a run.
SHARPNESS_STARTS = (0.1, 1.0, 10.0)
# Under RK4 a step's velocity change in one channel depends on every force at its stages: each
# channel is fitted beside the others' laws as found so far, and again while that gets closer.
RK4_PASSES = 3
# What the channels' coupling can leave in a channel fitted beside another's wrong law: a part in
# 1e5 of the force, some 1e2 to 1e3 x round-off (Hunt-Crossley beside the scene's friction:
# 594). A channel this far off fits no family whatever the others are: no pass again.
RK4_COUPLING_REACH = 1e6


def _rows(mask: np.ndarray, weight: np.ndarray | None = None) -> np.ndarray:
    idx = np.flatnonzero(mask)
    if idx.size <= FIT_ROWS:
        return idx
    spread = idx[np.linspace(0, idx.size - 1, FIT_ROWS // 2).astype(int)]
    if weight is None:
        return spread
    top = idx[np.argsort(weight[idx])[-FIT_ROWS // 2:]]
    return np.union1d(spread, top)


class RunIdentification:
    def __init__(self, states: np.ndarray, scene: Scene, rounding=None, source: str = "whole"):
        self.scene, self.rounding, self.source = scene, rounding, source
        self.sd = scene_dict(scene)
        self.geometry = Geometry.of_scene(self.sd)
        self.law_s = scene_law(scene, self.sd, self.geometry)
        states = np.asarray(states, dtype=float)
        self.Z0, self.Z1 = states[:-1], states[1:]
        self.H = np.full(len(self.Z0), scene.dt)
        self._base = {}

    def run(self) -> dict:
        return roundoff.in_own_context(self._run)

    def _run(self) -> dict:
        start = time.perf_counter()
        scene, law_s = self.scene, self.law_s
        Z0, Z1, H = self.Z0, self.Z1, self.H
        out = {"scene": scene.name, "from": self.source, "steps": len(Z0)}
        # float32 arithmetic behind float64 numbers: every bound below in single precision
        out["precision"] = "float32" if roundoff.is_float32(Z0, Z1) else "float64"
        roundoff.set_single_precision(out["precision"] == "float32")
        flight = self._flight()
        out["flight_steps"] = int(flight.sum())
        # gravity from the flight steps
        g = law_s.g
        if flight.any():
            a = (Z1[flight, 3:] - Z0[flight, 3:]) / H[flight, None]
            b = rate_bound(law_s.with_(normal=None), "semi_implicit_euler", Z0[flight], Z1[flight], H[flight],
                           self.rounding) / inertias(law_s)
            b = np.maximum(b, self._free_bound()[1][flight])   # the torque's floor: the weight's times the size
            w = weights(b[:, 1])
            g = float(np.sum(-a[:, 1] * w) / np.sum(w))
            res, rel = worst(a - np.array([0.0, -g, 0.0]), b)
            out["gravity"] = gravity_entry(g, res, rel, worst(a - np.array([0.0, -law_s.g, 0.0]), b)[1])
        else:   # at rest the weight and the spring share one equation (m g = k d): g is not read
            out["gravity"] = {"exercised": False, "g": None, "residual": None, "relative": None,
                              "scene_relative": None, "why": "no flight step (no run of steps under one constant "
                              "acceleration and nothing else: at rest m g = k d, gravity and the spring are "
                              "not told apart); the scene's g is taken"}
        self.forced = self._forced(g, out["gravity"].get("residual") or 0.0)
        self.onset = self._onset_seen(self.forced)
        # the integrator's class from the position update of every step
        tests = {}
        for name, share in POSITION_SHARE.items():
            rows = flight if name == "rk4" else np.ones(len(Z0), dtype=bool)
            if rows.any():
                tests[name] = worst(position_residual(Z0[rows], Z1[rows], H[rows], share),
                                    position_bound(name, Z0[rows], Z1[rows], H[rows], self.rounding))[1]
        law = law_s.with_(g=g)
        contact = scene.has("contact")
        beta, unc = position_share(Z0[flight], Z1[flight], H[flight], self.rounding)
        tests.update(beta=beta, beta_uncertainty=unc, depends_on_dt=None)   # a run has one dt
        shared = None   # no method's position update: the force held over the step, read at z0
        if tests.get("explicit_euler", np.inf) <= 1.0:
            candidates = ["explicit_euler"]
        elif tests.get("semi_implicit_euler", np.inf) <= 1.0:
            candidates = ["semi_implicit_euler", "implicit_euler"]
        elif beta is None or tests.get("rk4", np.inf) <= 1.0:
            candidates = ["rk4"]
        else:
            candidates, shared = ["explicit_euler"], "none: " + beta_words(beta)
        if not contact:
            name = candidates[0] if len(candidates) == 1 else None
            out["integrator"] = integrator_entry(name, candidates[0], tests.get(candidates[0], 0.0), tests,
                                                 "position update" if name else "no force depends on the state: "
                                                 "semi-implicit and implicit Euler coincide", scene)
            out.setdefault("gravity", gravity_entry(g, 0.0, 0.0, 0.0))
            for effect in ("normal", "friction", "rolling"):
                out[effect] = not_exercised(f"the scene does not list {EFFECT_OF[effect]}")
            out["body"] = self._body_entry(None)
            return self._finish(out, start)
        if len(candidates) > 1:   # semi-implicit or implicit Euler: those whose normal law fits
            first = {c: self._fit_laws(law, c, normal_only=True)["score"] for c in candidates}
            if min(first.values()) <= 1.0:
                candidates = [c for c in candidates if first[c] <= 1.0]
        results = {c: self._fit_laws(law, c) for c in candidates}
        if "rk4" in results:   # RK4's stages couple the channels: fit each again beside the others found
            for _ in range(RK4_PASSES):
                if results["rk4"]["score"] <= 1.0 or _farthest(results["rk4"]) > RK4_COUPLING_REACH:
                    break
                again = self._fit_laws(results["rk4"]["law"], "rk4")
                if not again["score"] <= results["rk4"]["score"]:   # inf while a channel fits no family
                    break
                results["rk4"] = again
        best = min(candidates, key=lambda c: results[c]["score"])
        res = results[best]
        fitting = [c for c in candidates if results[c]["score"] <= 1.0]
        if shared:
            name = None
        elif best == "explicit_euler":   # the position update alone names it (beta = 0 on every step)
            name = best
        else:                          # the others need a law that reproduces the run, under one only
            name = best if len(fitting) == 1 and best in fitting else None
        rel = max(tests.get(best, 0.0), res["score"]) if best == "rk4" else tests.get(best, 0.0)
        why = {"explicit_euler": "position update q1 = q0 + h v0 on every step",
               "semi_implicit_euler": "position update q1 = q0 + h v1, and the laws fit with the force at z0",
               "implicit_euler": "position update q1 = q0 + h v1, and the laws fit with the force at z1",
               "rk4": "the laws stepped by RK4 reproduce every step"}[best]
        if len(fitting) > 1:
            why = ("semi-implicit and implicit Euler both reproduce every step, each with its own laws: the run "
                   "never tells them apart")
        elif shared:
            why = shared + ("; the laws read with the force at the start of each step" if res["score"] <= 1.0 else "")
            best = min(("explicit_euler", "semi_implicit_euler", "rk4"), key=lambda k: tests.get(k, np.inf))
            rel = tests.get(best, np.inf)
        elif name is None:
            why = "no integrator with any of the families reproduces the steps"
        out["integrator"] = integrator_entry(name, best, rel, tests, why, scene)
        for effect in ("normal", "friction", "rolling"):
            out[effect] = res[effect]
        out["body"] = self._body_entry(res["body"])
        settle_body(out, ("normal", "friction", "rolling"))
        return self._finish(out, start)

    def _bound(self, integrator: str, g: float) -> np.ndarray:
        """The round-off bound of every step under the scene's law (with the state's uncertainty
        carried through it: a file's rounding of y is k dy, far above the velocity's at rest),
        once per integrator: the weights of every fit and the floor of every check."""
        if integrator not in self._base:
            self._base[integrator] = rate_bound(self.law_s.with_(g=g), integrator, self.Z0, self.Z1, self.H,
                                                self.rounding)
        return self._base[integrator]

    def _compare(self, law: Law, integrator: str, Z0, Z1, H, rnd) -> forward.Stepped:
        """forward.compare over every step, its bound floored by the scene's law's (_bound)."""
        return forward.compare(law, integrator, Z0, Z1, H, rnd, base=self._bound(integrator, law.g))

    def _worst(self, law: Law, integrator: str, rows: np.ndarray, channels: list[int]) -> tuple[float, float]:
        """(largest residual, relative) of a candidate over the rows: first over a sample of
        them (a family that fails there fails), then, if it passes, over every row."""
        Z0, Z1, H, rnd = self.Z0, self.Z1, self.H, self.rounding
        base = self._bound(integrator, law.g)
        sample = rows[np.linspace(0, rows.size - 1, min(rows.size, FIT_ROWS)).astype(int)] if rows.size else rows
        for part in (sample, rows):
            st = forward.compare(law, integrator, Z0[part], Z1[part], H[part], rnd, base=base[part])
            res, rel = st.worst(np.arange(part.size), channels)
            if rel > 1.0 or part is rows:
                return res, rel
        return res, rel

    def _finish(self, out, start):
        out["keeps_state"] = False   # a run's states are read as given: no call is replayed
        out["matches_scene"] = matches(out, self.scene)
        out["seconds"] = time.perf_counter() - start
        return out

    def _body_entry(self, fit: dict | None) -> dict:
        b = body_entry(self.law_s, fit, None, [], self.scene, rotates=self.geometry.rotates)
        b.update({k: fit[k] for k in ("closest", "why") if fit and k in fit})
        if "closest" in b:
            b["inertia"] = None
        b["contact_points"] = self.geometry.points.tolist()
        b["contact_points_from"] = "the scene (a run does not locate them)"
        b["points_match"] = True
        return b

    def _free_bound(self) -> tuple[np.ndarray, np.ndarray]:
        """(velocity change over h (n, 3), its round-off bound (n, 3)) of every step, no force but
        gravity's (the file's rounding included)."""
        a = (self.Z1[:, 3:] - self.Z0[:, 3:]) / self.H[:, None]
        b = rate_bound(self.law_s.with_(normal=None, friction=None, rolling=None), "semi_implicit_euler",
                       self.Z0, self.Z1, self.H, self.rounding, sensitivity=False) / inertias(self.law_s)
        if self.geometry.rotates:   # a torque's round-off is at least the weight's times the body's size
            arm = max(self.geometry.size, 1e-3)
            b[:, 2] = np.maximum(b[:, 2], b[:, 1] * self.law_s.mass * arm / self.law_s.inertia)
        return a, b

    def _flight(self) -> np.ndarray:
        """The steps no force but a constant gravity acts on, from the forces seen, wherever the
        body is: no horizontal or angular velocity change beyond round-off, and one vertical
        acceleration shared by a run of steps whose vertical velocity spans at least
        FLIGHT_SPAN_STEPS steps of it (a body at rest on a force is no flight: its velocity does
        not move). Without gravity in the scene, the steps with no velocity change at all."""
        a, b = self._free_bound()
        quiet = (np.abs(a[:, 0]) <= b[:, 0]) & (np.abs(a[:, 2]) <= b[:, 2])
        idx = np.flatnonzero(quiet)
        if not self.scene.has("gravity"):
            return quiet & (np.abs(a[:, 1]) <= b[:, 1])
        flight = np.zeros(len(a), dtype=bool)
        if not idx.size:
            return flight
        order = idx[np.argsort(a[idx, 1])]
        ay, by = a[order, 1], b[order, 1]
        cut = np.flatnonzero(np.diff(ay) > by[1:] + by[:-1]) + 1
        best, best_n = None, 0
        for group in np.split(order, cut):
            g = -float(np.median(a[group, 1]))
            vy = self.Z0[group, 4]
            if abs(g) <= 100.0 * float(np.max(b[group, 1])):
                continue   # no acceleration: at rest (or moving uniformly), on a force or not
            if np.ptp(vy) < FLIGHT_SPAN_STEPS * abs(g) * float(np.max(self.H[group])) or group.size < best_n:
                continue
            best, best_n = group, group.size
        if best is not None:   # a chain of neighbours may drift: keep the steps within round-off of its g
            g = -float(np.median(a[best, 1]))
            flight[best[np.abs(a[best, 1] + g) <= b[best, 1]]] = True
        return flight

    def _forced(self, g: float, spread: float = 0.0) -> np.ndarray:
        """The steps whose velocity change differs from free fall under g beyond round-off and the
        spread (m/s^2) the flight steps g was read from show about it."""
        a, b = self._free_bound()
        return np.any(np.abs(a - np.array([0.0, -g, 0.0])) > b + np.array([0.0, spread, 0.0]), axis=1)

    def _onset_seen(self, forced: np.ndarray) -> float | None:
        """How high above the ground (m) the lowest point was at the highest step a force acted on,
        when above the step's own travel (a force that begins above the contact points), else None."""
        if not forced.any():
            return None
        c = contacts(self.law_s.with_(normal=None, friction=None, rolling=None), self.Z0[forced])
        height = -c.d.max(axis=1)
        travel = self.H[forced] * np.abs(c.vn).max(axis=1)
        top = int(np.argmax(height))
        return float(height[top]) if height[top] > travel[top] else None

    # -- the laws, under one integrator ---------------------------------------------------

    def _fit_laws(self, law: Law, integrator: str, normal_only: bool = False) -> dict:
        Z0, Z1, H, rnd = self.Z0, self.Z1, self.H, self.rounding
        approx = "explicit_euler" if integrator == "rk4" else integrator
        Ze = evaluated_at(approx, Z0, Z1)
        touching = contacts(law, Ze).touching.any(axis=1) | contacts(law, Z1).touching.any(axis=1) | self.forced
        out = {}
        # the normal law on the vertical channel
        rows = _rows(touching)
        fits, laws = [], {}
        for fam in FAMILIES["normal"]:
            start = law.normal[1] if law.normal and law.normal[0] is fam else self._start(None, fam)
            trial = law.with_(normal=(fam, start))
            slots = forward.family_slots(trial, "normal")
            if self.onset is not None:   # a force seen above the points: where it begins is fitted too
                trial = trial.with_(geometry=law.geometry.with_onset(self.onset))
                slots = slots + [("onset", 0)]
            for integ in (integrator,):
                trial = forward.fit(trial, slots, integ, Z0, Z1, H, rows, [1], rnd, self._bound(integ, law.g))
            fits.append(Fit(fam, trial.normal[1], *self._worst(trial, integrator, np.flatnonzero(touching), [1])))
            laws[fam.name] = trial
        named, also, closest = choose(fits, self.scene.contact.damping_law)
        law = laws[(named or closest).family.name]
        st_s = self._compare(law.with_(normal=self.law_s.normal, g=self.law_s.g, geometry=self.geometry), integrator,
                             Z0, Z1, H, rnd)
        scene_fit = Fit(self.law_s.normal[0], self.law_s.normal[1], *st_s.worst(np.flatnonzero(touching), [1]))
        out["normal"] = self._entry("normal", named, also, closest, fits, scene_fit, touching, 1, law, integrator)
        if self.onset is not None:   # where the force begins: the law's fitted onset, else the highest seen
            out["normal"]["onset"] = law.geometry.onset if named is not None else self.onset
            out["normal"]["onset_seen"] = self.onset
        law = self._downstream(law, "normal", scene_fit)
        scores = [(named or closest).relative]
        if normal_only:
            return {"score": scores[0]}
        # friction on the horizontal channel
        if law.friction is not None:
            law, entry, rel = self._fit_effect(law, "friction", integrator, approx, touching, 0)
            out["friction"] = entry
            scores.append(rel)
        else:
            out["friction"] = not_exercised(f"the scene does not list {EFFECT_OF['friction']}")
        # the inertia (and the rolling law) on the angular channel
        if self.geometry.rotates:
            law, entry, body = self._fit_torque(law, integrator, approx, touching)
            if out["friction"].get("exercised") and out["friction"]["law"] is None:
                # the torque carries the friction (r_y Ft): with no friction law, an inertia and a
                # rolling law fitted beside the closest one are no finding (an inertia of 0 fits)
                why = "not identified: the friction fits no family, and its torque r_y Ft enters this channel"
                body["closest"] = {"inertia": body["inertia"], "residual": body["residual"],
                                   "relative": body["relative"]}
                body.update(inertia=None, residual=None, relative=None, why=why)
                if entry.get("exercised"):
                    entry = {**entry, "law": None, "residual": None, "relative": None, "why": why,
                             "closest": entry.get("closest") or {"law": entry["law"], "residual": entry["residual"],
                                                                 "relative": entry["relative"]}}
            out["rolling"] = entry
            out["body"] = body
            scores.append(body["relative"] if body["relative"] is not None else np.inf)
            if entry.get("exercised"):
                scores.append((entry.get("relative") if entry["law"] else entry["closest"]["relative"]) or 0.0)
        else:
            st = self._compare(law, integrator, Z0, Z1, H, rnd)
            res, rel = st.worst(np.arange(len(Z0)), [2])
            out["rolling"] = not_exercised(f"the scene does not list {EFFECT_OF['rolling']}")
            out["body"] = {"inertia": 0.0, "residual": res, "relative": rel, "scene_relative": rel}
            scores.append(rel)
        st = self._compare(law, integrator, Z0, Z1, H, rnd)
        out["score"] = max(max(scores), st.worst(np.arange(len(Z0)), [0, 1, 2])[1])
        out["law"] = law
        return out

    def _start(self, part, fam) -> tuple:
        """A family's starting parameters from the scene's law (its own where it names them)."""
        ct = self.scene.contact
        if fam.effect == "normal":
            if fam.name == "hunt_crossley":   # c v_n = k d D v_n at the resting depth d = m g / k
                rest = max(self.sd["mass_properties"]["mass"] * 9.81 / ct.k, 1e-6)
                return (ct.k, ct.dissipation or ct.c / (ct.k * rest))
            return (ct.k, ct.c)
        if fam.effect == "friction":
            return {"sign": (ct.mu,), "none": ()}.get(fam.name, (ct.mu, ct.alpha or 100.0))
        return {"sign": (ct.mu_roll,), "none": ()}.get(fam.name, (ct.mu_roll, ct.roll_sharpness or 100.0))

    def _fit_effect(self, law: Law, effect: str, integrator: str, approx: str, touching, channel: int):
        Z0, Z1, H, rnd = self.Z0, self.Z1, self.H, self.rounding
        weight = np.abs(Z1[:, 3 + channel] - Z0[:, 3 + channel])
        rows = _rows(touching, weight)
        fits, laws = [], {}
        for fam in FAMILIES[effect]:
            base = self._start(None, fam)
            starts = [base] if len(base) < 2 else [(base[0], base[1] * s) for s in SHARPNESS_STARTS]
            best = None
            scout = SCOUT_EVALUATIONS if len(starts) > 1 else LSQ_MAX_EVALUATIONS
            for p in starts:
                trial = law.with_(**{effect: (fam, p)})
                slots = forward.family_slots(trial, effect)
                trial = forward.fit(trial, slots, integrator, Z0, Z1, H, rows, [channel], rnd,
                                    self._bound(integrator, law.g), scout)
                r = self._worst(trial, integrator, np.flatnonzero(touching), [channel])
                if best is None or r[1] < best[1][1]:
                    best = (trial, r)
            if len(starts) > 1:   # the best start polished to round-off
                trial = forward.fit(best[0], forward.family_slots(best[0], effect), integrator, Z0, Z1, H, rows,
                                    [channel], rnd, self._bound(integrator, law.g))
                r = self._worst(trial, integrator, np.flatnonzero(touching), [channel])
                best = (trial, r) if r[1] <= best[1][1] else best
            fits.append(Fit(fam, getattr(best[0], effect)[1], *best[1]))
            laws[fam.name] = best[0]
        field = {"friction": "friction_law", "rolling": "roll_law"}[effect]
        named, also, closest = choose(fits, getattr(self.scene.contact, field))
        law = laws[(named or closest).family.name]
        st_s = self._compare(law.with_(**{effect: getattr(self.law_s, effect)}), integrator, Z0, Z1, H, rnd)
        part = getattr(self.law_s, effect)
        scene_fit = Fit(part[0], part[1], *st_s.worst(np.flatnonzero(touching), [channel]))
        entry = self._entry(effect, named, also, closest, fits, scene_fit, touching, channel, law, integrator)
        return self._downstream(law, effect, scene_fit), entry, (named or closest).relative

    def _downstream(self, law: Law, effect: str, scene_fit: Fit) -> Law:
        """The law the next effects are fitted with: the scene's own family and parameters where
        they reproduce the run as well (to the rounding a file allows, a fitted parameter also
        carries that rounding, which the next channel would take for its own residual)."""
        return law.with_(**{effect: getattr(self.law_s, effect)}) if scene_fit.relative <= 1.0 else law

    def _fit_torque(self, law: Law, integrator: str, approx: str, touching):
        Z0, Z1, H, rnd = self.Z0, self.Z1, self.H, self.rounding
        everything = np.arange(len(Z0))
        weight = np.abs(Z1[:, 5] - Z0[:, 5])
        rows = _rows(np.ones(len(Z0), dtype=bool), weight)
        fams = FAMILIES["rolling"] if law.rolling is not None else (None,)
        results = []
        for fam in fams:
            base = () if fam is None else self._start(None, fam)
            starts = [base] if len(base) < 2 else [(base[0], base[1] * s) for s in SHARPNESS_STARTS]
            best = None
            scout = SCOUT_EVALUATIONS if len(starts) > 1 else LSQ_MAX_EVALUATIONS
            for p in starts:
                trial = law if fam is None else law.with_(rolling=(fam, p))
                slots = ([] if fam is None else forward.family_slots(trial, "rolling")) + [("inertia", 0)]
                trial = forward.fit(trial, slots, integrator, Z0, Z1, H, rows, [2], rnd, self._bound(integrator, law.g),
                                    scout)
                r = self._worst(trial, integrator, everything, [2])
                if best is None or r[1] < best[1][1]:
                    best = (trial, r)
            if len(starts) > 1:   # the best start polished to round-off
                slots = forward.family_slots(best[0], "rolling") + [("inertia", 0)]
                trial = forward.fit(best[0], slots, integrator, Z0, Z1, H, rows, [2], rnd,
                                    self._bound(integrator, law.g))
                r = self._worst(trial, integrator, everything, [2])
                best = (trial, r) if r[1] <= best[1][1] else best
            results.append(best)
        if law.rolling is not None:
            fits = [Fit(t.rolling[0], t.rolling[1], *r) for t, r in results]
            named, also, closest = choose(fits, self.scene.contact.roll_law)
            pick = results[fits.index(named or closest)][0]
            st_s = self._compare(pick.with_(rolling=self.law_s.rolling), integrator, Z0, Z1, H, rnd)
            scene_fit = Fit(self.law_s.rolling[0], self.law_s.rolling[1], *st_s.worst(everything, [2]))
            entry = self._entry("rolling", named, also, closest, fits, scene_fit, touching, 2, pick, integrator)
        else:
            pick = results[0][0]
            entry = not_exercised(f"the scene does not list {EFFECT_OF['rolling']}")
        st = self._compare(pick, integrator, Z0, Z1, H, rnd)
        res, rel = st.worst(everything, [2])
        st_s = self._compare(pick.with_(inertia=self.law_s.inertia), integrator, Z0, Z1, H, rnd)
        body = {"inertia": pick.inertia, "lx": float("nan"), "residual": res, "relative": rel,
                "scene_relative": st_s.worst(everything, [2])[1]}
        return pick, entry, body

    def _entry(self, effect, named, also, closest, fits, scene_fit, touching, channel, law, integrator) -> dict:
        """The effect's entry, with whether any step exercised it above round-off."""
        entry = effect_entry(effect, named, also, closest, fits, scene_fit)
        # exercised: the effect's own force (the law found) above the step's round-off somewhere
        # (the law found, or the scene's: a run where the scene's friction would act and the
        # step has none exercises it, and finds "none")
        Ze = evaluated_at(integrator, self.Z0, self.Z1)
        base = self._base.get(integrator)
        scale = base[:, channel] if base is not None else 0.0
        acting = np.zeros(len(self.Z0), dtype=bool)
        for which in (law, law.with_(**{effect: getattr(self.law_s, effect)})):
            c = contacts(which, self.Z0 if Ze is None else Ze)
            own = {"normal": c.fn, "friction": c.ft, "rolling": c.roll}[effect]
            acting |= np.abs(np.where(c.touching, own, 0.0).sum(axis=1)) > scale
        entry["steps_acting"] = int(np.sum(acting & touching))
        if not entry["steps_acting"]:   # nothing to read a law from: null, never the scene's or a fit to zero
            entry = {**not_exercised(f"no step of the run has a {effect} force above its round-off"),
                     "steps_acting": 0, "scene_relative": entry["scene_relative"]}
        elif also:
            entry["why"] = (f"the run never separates {', '.join([entry['law'], *also])}: "
                            "each reproduces every step")
        return entry


def _farthest(result: dict) -> float:
    """The largest relative residual of a fit's effects (their law's, else their closest's)."""
    worst_rel = 0.0
    for effect in ("normal", "friction", "rolling", "body"):
        e = result.get(effect) or {}
        rel = e.get("relative")
        if rel is None:
            rel = (e.get("closest") or {}).get("relative")
        if rel is not None:
            worst_rel = max(worst_rel, float(rel))
    return worst_rel


def identify_run(states, scene: Scene, rounding=None, source: str = "whole") -> dict:
    """The identification of one scene from its run's states (steps + 1, 6)."""
    return RunIdentification(states, scene, rounding, source).run()
