"""The dynamics twin's contact forces: the scene's contact law, any family (contact_law.py), applied
through MuJoCo's passive-force callback, as a compiled function pointer (numba cfunc: no GIL, no
Python per call).

    installed(model, data, params)      context manager: register a run's MjData, install the callback
    law_parameters(scene, rb, below, native_normal=, friction_at=)   the callback's parameter row
    apply_contact_law(m, d, slot)       per touching site: Jp' (0, 0, Fn) + Jp_f' (Ft, 0, 0)
                                        + Jr' (0, -tau, 0) added to qfrc_passive (N, N m)

Switches: native_normal (MuJoCo's condim-1 pairs make the normal force, the callback adds
friction and rolling) and friction_at ("corner" or "midpoint", d/2 up). The callback finds its
run's data in a registry by the MjData's address; it names the registry and mj_jac by symbol so
that numba caches it on disk. How and why:
docs/mujoco-twins.md#the-dynamics-twin-dynamicspy-passivepy-contact_lawpy.
"""
from __future__ import annotations

import ctypes
import glob
import os
import threading
from contextlib import contextmanager

import llvmlite.binding
import mujoco
import numpy as np
from llvmlite import ir
from numba import carray, cfunc, njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from .compile_cache import clear_if_sources_changed
from .contact_law import (DAMPING_CODES, FRICTION_CODES, ROLL_CODES, friction_force, normal_force,
                          rolling_torque)

# parameters of one run (float64), by index
(P_CONTACT, P_FRICTION, P_ROLLING, P_LAW, P_K, P_C, P_MU, P_ALPHA, P_MU_ROLL, P_BELOW,
 P_NATIVE_NORMAL, P_MIDPOINT, P_BODY, P_DISSIPATION, P_FRICTION_LAW, P_ROLL_LAW, P_ROLL_SHARPNESS,
 N_PARAMS) = range(18)
# the scene's law field -> the codes of the families the callback implements
LAW_CODES = {"damping_law": DAMPING_CODES, "friction_law": FRICTION_CODES, "roll_law": ROLL_CODES}
# registry fields of one slot (int64), by index
(R_DATA, R_QVEL, R_QFRC, R_SITE_XPOS, R_SCRATCH, R_PARAMS, R_NV, R_NSITE, R_CALLS,
 N_FIELDS) = range(10)
SLOTS = 64   # MjData run at once in one process (threads), far above the cores we have
FRICTION_AT = ("corner", "midpoint")


def _mujoco_library() -> ctypes.CDLL:
    """The MuJoCo shared library the bindings loaded (the same file: dlopen returns its handle)."""
    folder = os.path.dirname(mujoco.__file__)
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        found = sorted(glob.glob(os.path.join(folder, pattern)))
        if found:
            return ctypes.CDLL(found[0])
    raise ImportError(f"no MuJoCo shared library next to {mujoco.__file__}")


REGISTRY_SYMBOL = "mujoco_models_passive_registry"
MJ_JAC_SYMBOL = "mujoco_models_mj_jac"


@intrinsic
def _mj_jac(typingctx, m, d, jacp, jacr, point, body):
    """mj_jac(m, d, jacp, jacr, point, body), MuJoCo's C function, called by symbol; the
    arrays by their int64 addresses."""
    def codegen(context, builder, signature, args):
        vp = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [vp] * 5 + [ir.IntType(32)])
        fn = cgutils.get_or_insert_function(builder.module, fnty, MJ_JAC_SYMBOL)
        mm, dd, jp, jr, pt, b = args
        builder.call(fn, [mm, dd, builder.inttoptr(jp, vp), builder.inttoptr(jr, vp),
                          builder.inttoptr(pt, vp), builder.trunc(b, ir.IntType(32))])
        return context.get_dummy_value()
    return types.void(types.voidptr, types.voidptr, types.int64, types.int64, types.int64, types.int64), codegen


@intrinsic
def _registry_address(typingctx):
    """The registry's address, by symbol."""
    def codegen(context, builder, signature, args):
        try:
            gv = builder.module.get_global(REGISTRY_SYMBOL)
        except KeyError:
            gv = ir.GlobalVariable(builder.module, ir.IntType(64), name=REGISTRY_SYMBOL)
            gv.linkage = "external"
        return builder.ptrtoint(gv, ir.IntType(64))
    return types.int64(), codegen


@intrinsic
def _f64(typingctx, address):
    """An int64 address as a float64 pointer."""
    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], context.get_value_type(types.CPointer(types.float64)))
    return types.CPointer(types.float64)(types.int64), codegen


@intrinsic
def _i64(typingctx, address):
    """An int64 address as an int64 pointer."""
    def codegen(context, builder, signature, args):
        return builder.inttoptr(args[0], context.get_value_type(types.CPointer(types.int64)))
    return types.CPointer(types.int64)(types.int64), codegen


@intrinsic
def _address(typingctx, pointer):
    """A void pointer's address as an int64."""
    def codegen(context, builder, signature, args):
        return builder.ptrtoint(args[0], context.get_value_type(types.int64))
    return types.int64(types.voidptr), codegen


@njit(cache=True)
def _jacobian(m, d, scratch_address, nv, body, x, y, z):
    """mj_jac at the world point (x, y, z) into the scratch: Jp = scratch[0:3nv],
    Jr = scratch[3nv:6nv], the point at scratch[6nv:6nv+3]."""
    scratch = carray(_f64(scratch_address), (6 * nv + 3,))
    point = 6 * nv
    scratch[point], scratch[point + 1], scratch[point + 2] = x, y, z
    _mj_jac(m, d, scratch_address, scratch_address + 8 * 3 * nv, scratch_address + 8 * point, body)
    return scratch


@njit(cache=True)
def apply_contact_law(m, d, slot):
    """Add the contact law's generalised forces of every touching site to qfrc_passive
    (docs/mujoco-twins.md#the-dynamics-twin-dynamicspy-passivepy-contact_lawpy); slot: this
    data's registry row."""
    p = carray(_f64(slot[R_PARAMS]), (N_PARAMS,))
    if p[P_CONTACT] == 0.0:
        return
    nv, nsite = slot[R_NV], slot[R_NSITE]
    qvel = carray(_f64(slot[R_QVEL]), (nv,))
    qfrc = carray(_f64(slot[R_QFRC]), (nv,))
    xpos = carray(_f64(slot[R_SITE_XPOS]), (nsite, 3))
    body = np.int64(p[P_BODY])
    law = np.int64(p[P_LAW])
    friction_law, roll_law = np.int64(p[P_FRICTION_LAW]), np.int64(p[P_ROLL_LAW])
    for i in range(nsite):
        cx, cy, cz = xpos[i, 0], xpos[i, 1], xpos[i, 2] - p[P_BELOW]
        depth = -cz
        if depth <= 0.0:
            continue  # in the air: no force, no damping
        jac = _jacobian(m, d, slot[R_SCRATCH], nv, body, cx, cy, cz)
        vn = 0.0
        for j in range(nv):
            vn += jac[2 * nv + j] * qvel[j]          # Jp row z
        fn = normal_force(law, p[P_K], p[P_C], p[P_DISSIPATION], depth, vn)
        if p[P_NATIVE_NORMAL] == 0.0:
            for j in range(nv):
                qfrc[j] += jac[2 * nv + j] * fn
        if p[P_ROLLING] != 0.0:
            omega = 0.0
            for j in range(nv):
                omega -= jac[3 * nv + nv + j] * qvel[j]   # Jr row y: omega about -y
            tau = rolling_torque(roll_law, p[P_MU_ROLL], p[P_ROLL_SHARPNESS], fn, omega)
            for j in range(nv):
                qfrc[j] -= jac[3 * nv + nv + j] * tau     # Jr^T (0, -tau, 0)
        if p[P_FRICTION] != 0.0:
            if p[P_MIDPOINT] != 0.0:
                jac = _jacobian(m, d, slot[R_SCRATCH], nv, body, cx, cy, cz + 0.5 * depth)
            slip = 0.0
            for j in range(nv):
                slip += jac[j] * qvel[j]              # Jp row x at the friction point
            ft = friction_force(friction_law, p[P_MU], p[P_ALPHA], fn, slip)
            for j in range(nv):
                qfrc[j] += jac[j] * ft


_REGISTRY = np.zeros((SLOTS, N_FIELDS), dtype=np.int64)
llvmlite.binding.add_symbol(REGISTRY_SYMBOL, _REGISTRY.ctypes.data)
llvmlite.binding.add_symbol(MJ_JAC_SYMBOL, ctypes.cast(_mujoco_library().mj_jac, ctypes.c_void_p).value)


def _passive(m, d):
    registry = carray(_i64(_registry_address()), (SLOTS, N_FIELDS))
    key = _address(d)
    for s in range(SLOTS):
        if registry[s, R_DATA] == key:
            registry[s, R_CALLS] += 1
            apply_contact_law(m, d, registry[s])
            return


_compiled = None
_lock = threading.RLock()
_users = 0
_previous = None
_keep: dict[int, tuple] = {}   # slot -> the arrays its addresses point into


def callback():
    """The compiled callback (loaded from numba's cache, or compiled, on first use)."""
    global _compiled
    with _lock:
        if _compiled is None:
            clear_if_sources_changed()
            _compiled = cfunc(types.void(types.voidptr, types.voidptr), cache=True)(_passive)
        return _compiled


def law_code(contact, field: str) -> int:
    """The callback's code of the family a [contact] names in `field` (damping_law,
    friction_law, roll_law); ValueError naming the law when the callback does not implement it."""
    name = getattr(contact, field)
    codes = LAW_CODES[field]
    if name not in codes:
        raise ValueError(f"the dynamics twin's callback does not implement {field} = {name!r} "
                         f"(it implements: {', '.join(codes)})")
    return codes[name]


def _value(x) -> float:
    """A law parameter as float64; None (a parameter the family does not take) as NaN."""
    return float("nan") if x is None else float(x)


def law_parameters(scene, rb, below: float, *, native_normal: bool, friction_at: str) -> np.ndarray:
    """The callback's parameters for a scene: effect switches, the three law codes, k, c,
    dissipation, mu, alpha, mu_roll, roll_sharpness (NaN for an effect the scene does not list
    or a parameter its family does not take, so that a stray use shows), the depth offset below
    each site (m) and the switches. ValueError naming a law the callback does not implement."""
    if friction_at not in FRICTION_AT:
        raise ValueError(f"unknown friction_at {friction_at!r} (expected one of: {', '.join(FRICTION_AT)})")
    on, ct, nan = scene.has, scene.contact, float("nan")
    p = np.full(N_PARAMS, nan)
    p[P_CONTACT] = float(on("contact"))
    p[P_FRICTION] = float(on("contact") and on("friction"))
    p[P_ROLLING] = float(on("contact") and on("rolling_friction") and rb.rotates)
    p[P_LAW] = law_code(ct, "damping_law")
    p[P_FRICTION_LAW] = law_code(ct, "friction_law")
    p[P_ROLL_LAW] = law_code(ct, "roll_law")
    if on("contact"):
        p[P_K], p[P_C], p[P_DISSIPATION] = ct.k, ct.c, ct.dissipation
    if p[P_FRICTION]:
        p[P_MU], p[P_ALPHA] = ct.mu, _value(ct.alpha)
    if p[P_ROLLING]:
        p[P_MU_ROLL], p[P_ROLL_SHARPNESS] = ct.mu_roll, _value(ct.roll_sharpness)
    p[P_BELOW] = below
    p[P_NATIVE_NORMAL] = float(native_normal)
    p[P_MIDPOINT] = float(friction_at == "midpoint")
    p[P_BODY] = 1.0
    return p


class Registration:
    """One MjData's slot: `calls` counts the callback's evaluations of the law for it."""

    def __init__(self, slot: int):
        self.slot = slot

    @property
    def calls(self) -> int:
        return int(_REGISTRY[self.slot, R_CALLS])

    def reset_calls(self) -> None:
        _REGISTRY[self.slot, R_CALLS] = 0


@contextmanager
def installed(model: mujoco.MjModel, data: mujoco.MjData, params: np.ndarray):
    """Register `data` with the law's parameters and install the callback for the duration
    (the previous callback, if any, is restored when the last registered run leaves)."""
    global _users, _previous
    fn = callback()
    params = np.ascontiguousarray(params, dtype=np.float64)
    scratch = np.zeros(6 * model.nv + 3)
    with _lock:
        free = np.flatnonzero(_REGISTRY[:, R_DATA] == 0)
        if free.size == 0:
            raise RuntimeError(f"more than {SLOTS} dynamics twins running at once in one process")
        slot = int(free[0])
        _keep[slot] = (data, params, scratch)
        _REGISTRY[slot] = 0
        _REGISTRY[slot, R_QVEL] = data.qvel.ctypes.data
        _REGISTRY[slot, R_QFRC] = data.qfrc_passive.ctypes.data
        _REGISTRY[slot, R_SITE_XPOS] = data.site_xpos.ctypes.data
        _REGISTRY[slot, R_SCRATCH] = scratch.ctypes.data
        _REGISTRY[slot, R_PARAMS] = params.ctypes.data
        _REGISTRY[slot, R_NV] = model.nv
        _REGISTRY[slot, R_NSITE] = model.nsite
        _REGISTRY[slot, R_DATA] = data._address   # last: the slot is live from here on
        if _users == 0:
            _previous = mujoco.get_mjcb_passive()
            mujoco.set_mjcb_passive(fn.ctypes)
        _users += 1
    try:
        yield Registration(slot)
    finally:
        with _lock:
            _REGISTRY[slot] = 0
            _keep.pop(slot, None)
            _users -= 1
            if _users == 0:
                mujoco.set_mjcb_passive(_previous)
                _previous = None
