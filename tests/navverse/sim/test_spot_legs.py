"""The Spot model's native leg forces are the module's formulas evaluated in Python floats, bit for bit,
and the rollouts they drive are those of the Python formulas."""

from __future__ import annotations

import math
import struct

import numpy as np
import pytest

from navverse.sim import spot
from navverse.sim.world import OBJECT_FRICTION

BODY = 7
"""The trunk's body id in the synthetic steps below."""


def python_forces(state, velocity, command, hits, friction, body) -> tuple[float, ...]:
    """The leg forces of :mod:`navverse.sim.spot`'s docstring in Python floats: (force, torque, legs)."""
    (px, py, pz), (qx, qy, qz, qw) = state
    (vx, vy, vz), (wx, wy, wz) = velocity
    xx, yy, zz = qx * qx, qy * qy, qz * qz
    xy, xz, yz, wxq, wyq, wzq = qx * qy, qx * qz, qy * qz, qw * qx, qw * qy, qw * qz
    r00, r01, r02 = 1.0 - 2.0 * (yy + zz), 2.0 * (xy - wzq), 2.0 * (xz + wyq)
    r10, r11, r12 = 2.0 * (xy + wzq), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wxq)
    r20, r21, r22 = 2.0 * (xz - wyq), 2.0 * (yz + wxq), 1.0 - 2.0 * (xx + yy)
    cvx, cvy, cwz = command
    hn = math.hypot(r00, r10) or 1.0
    hx, hy = r00 / hn, r10 / hn
    tvx, tvy = cvx * hx - cvy * hy, cvx * hy + cvy * hx
    legs = [0.0] * 4
    fx = fy = fz = tx = ty = tz = 0.0
    grounds = [hit[3][2] for hit in hits if hit[0] >= 0 and hit[0] != body]
    mean_ground = sum(grounds) / len(grounds) if grounds else 0.0
    for i, (hit_body, _, fraction, hp, (nx, ny, nz)) in enumerate(hits):
        if hit_body < 0 or hit_body == body:
            continue
        rest = spot.LEG_REST + mean_ground - hp[2]
        rest = spot.LEG_MIN if rest < spot.LEG_MIN else (spot.LEG_REACH if rest > spot.LEG_REACH else rest)
        lx, ly, lz = spot._HIP_OFFSETS[i]
        ox = r00 * lx + r01 * ly + r02 * lz
        oy = r10 * lx + r11 * ly + r12 * lz
        oz = r20 * lx + r21 * ly + r22 * lz
        hvx, hvy, hvz = vx + wy * oz - wz * oy, vy + wz * ox - wx * oz, vz + wx * oy - wy * ox
        length = spot._RAY_START + fraction * spot._RAY_LENGTH
        push = spot.LEG_STIFFNESS * (rest - length) - spot.LEG_DAMPING * (hvx * r02 + hvy * r12 + hvz * r22)
        push = 0.0 if push < 0.0 else (spot.LEG_MAX_FORCE if push > spot.LEG_MAX_FORCE else push)
        legs[i] = push
        along = r02 * nx + r12 * ny + r22 * nz
        normal_load = push * along if along > 0.0 else 0.0
        ex, ey, ez = tvx - cwz * oy - hvx, tvy + cwz * ox - hvy, -hvz
        en = ex * nx + ey * ny + ez * nz
        share = spot._SHARE
        gx, gy, gz = share * (ex - en * nx), share * (ey - en * ny), share * (ez - en * nz)
        if nz > 0.5:
            hold = normal_load / nz
            gx -= hold * nz * nx + push * (r02 - along * nx)
            gy -= hold * nz * ny + push * (r12 - along * ny)
            gz += hold * (1.0 - nz * nz) - push * (r22 - along * nz)
        limit = friction.get(hit_body, OBJECT_FRICTION) * normal_load
        limit = spot.TRACTION_MAX if limit > spot.TRACTION_MAX else limit
        magnitude = math.sqrt(gx * gx + gy * gy + gz * gz)
        if magnitude > limit:
            scale = limit / magnitude
            gx, gy, gz = gx * scale, gy * scale, gz * scale
        ffx, ffy, ffz = push * r02 + gx, push * r12 + gy, push * r22 + gz
        rx, ry, rz = hp[0] - px, hp[1] - py, hp[2] - pz
        fx, fy, fz = fx + ffx, fy + ffy, fz + ffz
        tx += ry * ffz - rz * ffy
        ty += rz * ffx - rx * ffz
        tz += rx * ffy - ry * ffx
    return (fx, fy, fz, tx, ty, tz, *legs)


def _bits(values) -> list[bytes]:
    return [struct.pack("<d", v) for v in values]


def _random_step(rng: np.random.Generator):
    """A trunk state, a command and four ray hits like a rollout's, some legs in the air or on the trunk."""
    q = rng.normal(size=4) * np.array([0.1, 0.1, 1.0, 1.0])
    q /= np.linalg.norm(q)
    state = (tuple(rng.uniform(-50, 50, 3)), tuple(q))
    velocity = (tuple(rng.normal(0, 0.8, 3)), tuple(rng.normal(0, 0.8, 3)))
    command = tuple(rng.uniform(-1.5, 1.5, 3))
    hits = []
    for _ in range(4):
        kind = rng.random()
        if kind < 0.1:  # nothing under the leg
            hits.append((-1, -1, 1.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
            continue
        normal = rng.normal(size=3) * np.array([0.3, 0.3, 1.0]) + (np.array([0, 0, 1.0]) if kind < 0.9 else 0)
        normal /= np.linalg.norm(normal)
        body = BODY if kind > 0.97 else int(rng.integers(0, 6))  # the trunk itself, or a static body
        point = tuple(np.asarray(state[0]) + rng.normal(0, 0.5, 3))
        hits.append((body, -1, float(rng.uniform(0, 1)), point, tuple(normal)))
    friction = {0: 0.9, 1: 0.3, 2: 1, 3: 0.05}  # bodies 4 and 5 are objects: the default friction
    return state, velocity, command, tuple(hits), friction


def test_the_native_leg_forces_are_the_python_formulas_bit_for_bit() -> None:
    rng = np.random.default_rng(11)
    for _ in range(20_000):
        step = _random_step(rng)
        assert _bits(spot._LEGS.forces(*step, BODY)) == _bits(python_forces(*step, BODY)), step


def test_bad_arguments_are_refused() -> None:
    step = list(_random_step(np.random.default_rng(1)))
    step[3] = step[3][:3]  # three hits
    with pytest.raises(ValueError, match="hits must be a tuple of 4"):
        spot._LEGS.forces(*step, BODY)
