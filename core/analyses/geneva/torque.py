"""The crank torque of a Geneva drive from its contact model: the driving torque the motor applies
to the crank (N·m, counter-clockwise positive), the same quantity ``analyze --forces`` reports for
a linkage (``driver.torque``).

While the roller is in a slot the wheel receives the normal force R_n (the contact model's, with
the wheel-shaft journal friction of the derived form, notes B3) at the roller centre P,
perpendicular to the slot, i.e. to O2P. Its reaction on the roller has the lever arm about the
crank centre O1 of |(P − O1)·(P − O2)|/|O2P| = r·|cos u − λ|/√D (D = 1 − 2λ cos u + λ², u the
progress angle, λ = r/A), so the crank torque is

    T = sgn(ω1) · sgn(M) · R_n · r · |cos u − λ| / √D,

positive while the roller drives the wheel (M > 0) and negative in the braking half. Without
journal friction this equals the power balance T·ω1 = M·ω2, i.e. T = sgn(ω1)·M·i(u) with the
velocity ratio i = λ(cos u − λ)/D ≥ 0 (``frictionless`` below). In the dwell the locking disc
holds the wheel and the crank carries no load (0; the crank's own inertia is not modelled).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .contact import GenevaContact

if TYPE_CHECKING:
    from ...model.geneva import Geneva


@dataclass(frozen=True)
class GenevaTorque:
    """(N,) arrays over the crank revolution (the contact's rows): ``torque`` N·m with the contact
    model's normal force; ``frictionless`` N·m from the power balance M·ω2/ω1 (journal friction
    off); ``phi`` crank angle rad. Scalars: ``peak`` (N·m, signed) at ``phi_peak`` rad, ``rms``."""

    phi: np.ndarray
    torque: np.ndarray
    frictionless: np.ndarray
    peak: float
    phi_peak: float
    rms: float


def crank_torque(element: "Geneva", con: GenevaContact) -> GenevaTorque:
    """The crank torque of ``element`` over the revolution of ``con`` (see the module docstring)."""
    lam = element.lam
    r = element.crank_radius * 1e-3
    u = con.u
    cu = np.cos(u)
    d = 1.0 - 2.0 * lam * cu + lam * lam
    arm = r * np.abs(cu - lam) / np.sqrt(d)                      # m
    s = 1.0 if element.omega1 > 0 else -1.0
    eng = con.engaged
    m = np.where(eng, con.moment, 0.0)
    torque = np.where(eng, s * np.sign(m) * np.where(eng, con.Rn, 0.0) * arm, 0.0)
    frictionless = s * m * lam * (cu - lam) / d
    if torque.size:
        k = int(np.argmax(np.abs(torque)))
        peak, phi_peak = float(torque[k]), float(con.phi[k])
        rms = float(np.sqrt(np.mean(torque * torque)))
    else:
        peak, phi_peak, rms = 0.0, math.nan, 0.0
    return GenevaTorque(con.phi, torque, frictionless, peak, phi_peak, rms)
