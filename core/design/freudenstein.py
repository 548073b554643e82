"""Freudenstein's equations: four-bars and slider-cranks whose output follows a function of the
crank angle at precision points, in closed form.

**Four-bar** (crank pivot A at the origin, rocker pivot D at (d, 0); crank a, coupler b, rocker
c; input φ the crank's angle from A→D, output ψ the rocker's angle, both CCW):
``K1·cos ψ − K2·cos φ + K3 = cos(φ − ψ)`` with K1 = d/a, K2 = d/c, K3 = (a² − b² + c² + d²)/(2ac),
from |b|² = |d + c·e^{iψ} − a·e^{iφ}|². Three pairs (φ_j, ψ_j) give K1..K3 by one 3 × 3 linear
solve (more pairs: its least-squares solution, Freudenstein's structural error).

**Slider-crank** (crank pivot at the origin, the slider's pin on the line y = h; crank a, rod b;
output s the pin's x): ``K1·s·cos φ + K2·sin φ + K3 = s²`` with K1 = 2a, K2 = 2a·h,
K3 = b² − a² − h², from (s − a·cos φ)² + (h − a·sin φ)² = b².

The starting angles (φ0, ψ0 or the slider's start s0) are free: every function is solved at once
for a whole grid of them (arrays (G,) in, designs out). A design is returned in the parameters of
:mod:`.families` with its assembly mode, and crank angles normalised so that the crank length is
positive; lengths that do not close (b² ≤ 0) come out as NaN.
"""
from __future__ import annotations

import numpy as np

from . import families as F


def _solve(M: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Least-squares (exact for square) solution of M (G, n, 3) K = rhs (G, n), batched; NaN
    where M is singular."""
    MtM = np.einsum("gni,gnj->gij", M, M)
    Mtr = np.einsum("gni,gn->gi", M, rhs)
    det = np.linalg.det(MtM)
    scale = np.einsum("gii->g", MtM) ** 3
    bad = ~(np.abs(det) > 1e-13 * scale)
    MtM[bad] = np.eye(3)
    K = np.linalg.solve(MtM, Mtr[..., None])[..., 0]
    K[bad] = np.nan
    return K


def fourbar(phi: np.ndarray, psi: np.ndarray, d: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Four-bars through the pairs ``phi``, ``psi`` (G, n) rad (absolute angles, one row per choice
    of starting angles), ground d mm. Returns (designs (G, 9), modes (G,), crank angles (G, n))."""
    M = np.stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)], axis=-1)
    K = _solve(M, np.cos(phi - psi))
    with np.errstate(invalid="ignore", divide="ignore"):
        a, c = d / K[:, 0], d / K[:, 1]
        b2 = a * a + c * c + d * d - 2.0 * a * c * K[:, 2]
    th = phi + np.where(a < 0, np.pi, 0.0)[:, None]
    a, c = np.abs(a), c
    b = np.sqrt(np.where(b2 > 0, b2, np.nan))
    B1 = a * np.exp(1j * th[:, 0])
    C1 = d + c * np.exp(1j * psi[:, 0])
    sigma = np.sign(np.imag(np.conj(d - B1) * (C1 - B1)))
    z = np.zeros_like(a)
    x = np.stack([z, z, z + d, z, a, b, np.abs(c), z, z], axis=1)
    return x, sigma, th


def slider_crank(phi: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Slider-cranks through the pairs ``phi`` (G, n) rad and ``s`` (G, n) mm (absolute pin
    positions along the line, one row per choice of starting values). Returns (designs (G, 8),
    modes (G,), crank angles (G, n))."""
    M = np.stack([s * np.cos(phi), np.sin(phi), np.ones_like(phi)], axis=-1)
    K = _solve(M, s * s)
    with np.errstate(invalid="ignore", divide="ignore"):
        a = K[:, 0] / 2.0
        h = K[:, 1] / (2.0 * a)
        b2 = K[:, 2] + a * a + h * h
    th = phi + np.where(a < 0, np.pi, 0.0)[:, None]
    a = np.abs(a)
    b = np.sqrt(np.where(b2 > 0, b2, np.nan))
    sigma = np.sign(s[:, 0] - a * np.cos(th[:, 0]))
    z = np.zeros_like(a)
    x = np.stack([z, z, z, h, a, b, z, z], axis=1)
    return x, sigma, th


def outputs(topology: str, x: np.ndarray, sigma: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """(G, n) the output (rocker angle rad, or slider position mm) of each design at ``theta``."""
    return F.evaluate(topology, x, theta, sigma).out


__all__ = ["fourbar", "outputs", "slider_crank"]
