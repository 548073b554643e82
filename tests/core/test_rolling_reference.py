"""Independent references for the rolling lever (written apart from mechsketch's code), and their
own checks against the numbers of the notes (section C, default scene).

- :func:`mp_reference`: the ODE dα/dθ = 1 − g/ℓ, dS5/dθ = −t2 solved by mpmath's Taylor-series
  integrator at 20 digits (θ = −τ, since odefun marches forward).
- :func:`scipy_reference`: the same ODE with scipy's DOP853 at rtol 1e-13, the geometry coded again
  here in numpy.
- :func:`mp_theta_of_psi`: pair D seen from the lever depends only on the rocker direction
  ψ = α − θ, so the ODE separates and θ(ψ) is a quadrature (mpmath); used for working-range ends.
Other rolling tests import this module (``import test_rolling_reference as ref``).
"""
from __future__ import annotations

import functools
import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

PRESS = {"type": "rolling_lever", "id": "press",
         "lever_circle": {"center": [0, 0], "radius": 50}, "contact_branch": "near",
         "pin": [60, -20], "rocker_pivot": [-150, -40],
         "slider_circle": {"center": [20, 0], "radius": 80}, "slider_axis_deg": 0, "slider_side": 1,
         "stroke": {"from": 0.0, "to": -0.5926},
         "method": "exact", "points": 200,
         "drive": {"crank_pivot": [-60, 120], "coupler_point": [30, 40]}}


def scene_of(*elements) -> dict:
    return {"format": "mechsketch.scene", "schema_version": 1, "units": "mm", "elements": list(elements)}


def element(**changes):
    """The notes' default scene as an element, with top-level keys replaced."""
    from mechsketch.core.model.rolling_lever import parse

    d = dict(PRESS)
    d.update(changes)
    for k in [k for k, v in d.items() if v is None]:
        del d[k]
    el, problems = parse(d, "$")
    assert not problems, problems
    return el


class Geo:
    """Plain-float geometry of a rolling-lever dict (numpy, vectorised over θ)."""

    def __init__(self, d: dict) -> None:
        self.G = np.array(d["rocker_pivot"], float)
        self.f = np.array(d["pin"], float)
        self.c1 = np.array(d["lever_circle"]["center"], float)
        self.R1 = float(d["lever_circle"]["radius"])
        self.c2 = np.array(d["slider_circle"]["center"], float)
        self.R2 = float(d["slider_circle"]["radius"])
        ax = math.radians(d.get("slider_axis_deg", 0.0))
        self.ds = np.array([math.cos(ax), math.sin(ax)])
        self.n = np.array([-self.ds[1], self.ds[0]])
        self.side = d.get("slider_side", 1)
        self.br = 1.0 if d.get("contact_branch", "near") == "far" else -1.0
        self.ell = float(np.linalg.norm(self.f - self.G))
        self.a0 = math.atan2(*(self.f - self.G)[::-1])

    def lever(self, a, th, p):
        """X(p) for lever point p (2,) at poses (α, θ) (M,)."""
        a, th = np.atleast_1d(a), np.atleast_1d(th)
        F = self.G + self.ell * np.stack([np.cos(a), np.sin(a)], -1)
        v = p - self.f
        return F + np.stack([np.cos(th) * v[0] - np.sin(th) * v[1], np.sin(th) * v[0] + np.cos(th) * v[1]], -1)

    def contact(self, a, th):
        """(g, P, C1, t2, P0, C2) at poses (α, θ) (M,)."""
        a, th = np.atleast_1d(a), np.atleast_1d(th)
        e = np.stack([np.cos(a), np.sin(a)], -1)
        C1 = self.lever(a, th, self.c1)
        w = C1 - self.G
        b = (w * e).sum(1)
        g = b + self.br * np.sqrt(b * b - (w * w).sum(1) + self.R1 ** 2)
        P = self.G + g[:, None] * e
        C2 = self.lever(a, th, self.c2)
        z = P - C2
        zn = z @ self.n
        t2 = -zn + self.side * np.sqrt(zn * zn - (z * z).sum(1) + self.R2 ** 2)
        return g, P, C1, t2, P + t2[:, None] * self.n, C2

    def rhs(self, th, y):
        g, _, _, t2, _, _ = self.contact(np.array([y[0]]), np.array([th]))
        return [1.0 - g[0] / self.ell, -t2[0]]


def scipy_reference(d: dict, theta: np.ndarray):
    """(α, S5) at θ (monotone, moving away from 0) by DOP853, rtol 1e-13."""
    geo = Geo(d)
    sol = solve_ivp(geo.rhs, (0.0, float(theta[-1])), [geo.a0, 0.0], method="DOP853", rtol=1e-13, atol=1e-14,
                    t_eval=theta, dense_output=False)
    assert sol.success
    return sol.y[0], sol.y[1]


@functools.lru_cache(maxsize=4)
def mp_reference(key: str, dps: int = 20):
    """mpmath.odefun solution for the default scene; returns a function θ -> (α, S5) (mpf)."""
    assert key == "press"
    mp.mp.dps = dps
    G = (mp.mpf(-150), mp.mpf(-40))
    f = (mp.mpf(60), mp.mpf(-20))
    c2 = (mp.mpf(20), mp.mpf(0))
    R1, R2 = mp.mpf(50), mp.mpf(80)
    ell = mp.sqrt((f[0] - G[0]) ** 2 + (f[1] - G[1]) ** 2)
    a0 = mp.atan2(f[1] - G[1], f[0] - G[0])

    def rates(a, th):
        ca, sa, ct, st = mp.cos(a), mp.sin(a), mp.cos(th), mp.sin(th)
        F = (G[0] + ell * ca, G[1] + ell * sa)
        C = (F[0] - ct * f[0] + st * f[1], F[1] - st * f[0] - ct * f[1])  # c1 = origin
        w = (C[0] - G[0], C[1] - G[1])
        b = w[0] * ca + w[1] * sa
        g = b - mp.sqrt(b * b - (w[0] ** 2 + w[1] ** 2 - R1 ** 2))
        P = (G[0] + g * ca, G[1] + g * sa)
        v = (c2[0] - f[0], c2[1] - f[1])
        z = (P[0] - F[0] - ct * v[0] + st * v[1], P[1] - F[1] - st * v[0] - ct * v[1])
        t2 = -z[1] + mp.sqrt(z[1] ** 2 - (z[0] ** 2 + z[1] ** 2) + R2 ** 2)
        return 1 - g / ell, -t2

    sol = mp.odefun(lambda tau, y: [-r for r in rates(y[0], -tau)], 0, [a0, mp.mpf(0)])
    return lambda th: sol(-mp.mpf(th))


def mp_lever_frame(d: dict, dps: int = 30):
    """Pair D seen from the lever, in mpmath: returns (ψ0, g(ψ), D(ψ), b(ψ)) for the rocker direction
    ψ = α − θ. In the lever frame the rocker line passes through the pin f with direction e(ψ) and
    the pivot sits at f − ℓ e(ψ), so b (projection of c1 − G on the line), the discriminant D and
    the contact distance g depend on ψ alone (D clamped at 0 for g)."""
    mp.mp.dps = dps
    G = [mp.mpf(x) for x in d["rocker_pivot"]]
    f = [mp.mpf(x) for x in d["pin"]]
    c = [mp.mpf(x) for x in d["lever_circle"]["center"]]
    R = mp.mpf(d["lever_circle"]["radius"])
    br = 1 if d.get("contact_branch", "near") == "far" else -1
    ell = mp.sqrt((f[0] - G[0]) ** 2 + (f[1] - G[1]) ** 2)

    def parts(psi):
        e = (mp.cos(psi), mp.sin(psi))
        w = (c[0] - f[0] + ell * e[0], c[1] - f[1] + ell * e[1])
        b = w[0] * e[0] + w[1] * e[1]
        return b, b * b - (w[0] ** 2 + w[1] ** 2 - R ** 2)

    def g(psi):
        b, D = parts(psi)
        return b + br * mp.sqrt(max(D, 0))

    return mp.atan2(f[1] - G[1], f[0] - G[0]), g, (lambda psi: parts(psi)[1]), (lambda psi: parts(psi)[0])


def mp_theta_of_psi(d: dict, psi_end, dps: int = 30):
    """θ at which the rocker direction seen from the lever, ψ = α − θ, reaches ``psi_end``: pair D
    depends on ψ alone, so dα/dθ = 1 − g/ℓ separates into dθ/dψ = −ℓ/g(ψ) and
    θ = −ℓ ∫_{ψ0}^{ψ_end} dψ/g(ψ) (mpmath's tanh-sinh quadrature copes with the square root of g at
    a tangent). Independent of any step-by-step integration."""
    psi0, g, _, _ = mp_lever_frame(d, dps)
    G = [mp.mpf(x) for x in d["rocker_pivot"]]
    f = [mp.mpf(x) for x in d["pin"]]
    ell = mp.sqrt((f[0] - G[0]) ** 2 + (f[1] - G[1]) ** 2)
    return -ell * mp.quad(lambda p: 1 / g(p), [psi0, mp.mpf(psi_end)])


# -- the references against the notes ----------------------------------------------------------
def test_mpmath_reference_reproduces_the_notes_default_scene():
    a, s5 = mp_reference("press")(-0.5926)
    assert abs(float(s5) - 50.43) < 0.01  # notes: S5 = 50.43 mm
    geo = Geo(PRESS)
    _, P, C1, t2, _, _ = geo.contact(np.array([float(a)]), np.array([-0.5926]))
    r = P[0] - C1[0]  # contact angle in the lever frame: rotate back by θ
    u_end = math.degrees(math.atan2(r[1], r[0]) + 0.5926)
    assert abs(u_end - (-93.9)) < 0.05  # notes: the stroke ends at the position-1 tangent point
    # the position-1 tangent point from G is at −93.857°; θ = −0.5926 (4 decimals, du/dθ ≈ 84°/rad)
    # reaches it to within 0.005°
    tangent = math.degrees(math.atan2(geo.G[1], geo.G[0]) + math.acos(geo.R1 / np.linalg.norm(geo.G)))
    assert abs(u_end - tangent) < 5e-3


def test_scipy_and_mpmath_references_agree():
    th = np.linspace(0.0, -0.5926, 5)
    a, s = scipy_reference(PRESS, th)
    ref = mp_reference("press")
    for t, ai, si in zip(th[1:], a[1:], s[1:]):
        am, sm = ref(t)
        assert abs(ai - float(am)) < 1e-12
        assert abs(si - float(sm)) < 1e-10


def test_reference_geometry_matches_the_notes_ranges():
    th = np.linspace(0.0, -0.5926, 201)
    a, _ = scipy_reference(PRESS, th)
    geo = Geo(PRESS)
    g, P, _, t2, _, _ = geo.contact(a, th)
    rate = 1 - g / geo.ell
    assert rate.min() == pytest.approx(0.33, abs=0.005) and rate.max() == pytest.approx(0.48, abs=0.005)
    assert (-t2).max() == pytest.approx(-82, abs=0.5) and (-t2).min() == pytest.approx(-93, abs=0.5)
    assert np.hypot(*np.diff(P, axis=0).T).sum() == pytest.approx(43.55, abs=0.01)
