"""The integrators a scene may name, ours and MuJoCo's, and how they correspond: written once.

Ours (the seed's four methods) and MuJoCo's differ in name. What matters for a comparison is
the update: MuJoCo's Euler, implicit and implicitfast all update velocity first and then
position with the new velocity (contact forces explicit), which is our semi-implicit Euler;
MuJoCo's RK4 is the classical four stages, our rk4. Only Euler and RK4 integrate a passive
force the way ours do (the implicit ones leave it out of their derivatives), so they are the
twins the dynamics check can use.
"""
from __future__ import annotations

OURS = ("explicit_euler", "semi_implicit_euler", "implicit_euler", "rk4")
MUJOCO = ("Euler", "RK4", "implicit", "implicitfast")

# each MuJoCo integrator -> ours with the same position and velocity update
SAME_UPDATE = {"Euler": "semi_implicit_euler", "RK4": "rk4",
               "implicit": "semi_implicit_euler", "implicitfast": "semi_implicit_euler"}
# ours -> the MuJoCo integrator that integrates a passive force with our update
MUJOCO_TWIN = {"semi_implicit_euler": "Euler", "rk4": "RK4"}
# the order of convergence of each (global error ~ dt^order on a smooth motion)
ORDER = {"explicit_euler": 1, "semi_implicit_euler": 1, "implicit_euler": 1, "rk4": 4,
         "Euler": 1, "implicit": 1, "implicitfast": 1, "RK4": 4}
