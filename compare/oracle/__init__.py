"""The independent oracle: the scene's model written a second way, from the scene file alone.

rigid_body.py (mass properties by Green's theorem), force_law.py (the contact law in numpy),
reference.py (the equations of motion and the converged reference solution). It takes nothing
from custom_sim but the scene's schema, so a check built on it can tell custom_sim, or a user's
simulator, wrong.
"""
