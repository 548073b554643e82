"""The linkage topologies synthesis designs, in closed form over (designs, samples) with exact
derivatives: the four-bar (RRR), the slider-crank (RRP) and the inverted slider-crank (RPR).

A design is a parameter vector in the world frame (mm, rad), one row per design:

=========================  =====================================================================
``fourbar``                Ax Ay Dx Dy a b c px py — crank pivot A, rocker pivot D, crank AB = a,
                           coupler BC = b, rocker DC = c; the coupler point P = B + (px + i·py)·
                           (C − B)/b (its coordinates in the coupler's frame: x along B→C)
``slider_crank``           Ax Ay g h a b px py — crank pivot A; the slider's pin C moves on the
                           line {A + (s + i·h)·e^{ig}} (direction g rad, offset h mm from A);
                           crank a, rod BC = b; P = B + (px + i·py)·(C − B)/b
``inverted_slider_crank``  Ax Ay Gx Gy a e px py — crank pivot A, rocker pivot G; the crank pin
                           B slides in a guide of the rocker at offset e from G (u: the guide's
                           direction); the block carries P = B + (px + i·py)·u
``sixbar``                 Ax Ay Dx Dy a b c ex ey Fx Fy l1 l2 px py — a Stephenson III six-bar:
                           the four-bar A B C D with a point E = B + (ex + i·ey)·(C − B)/b on its
                           connector, and a dyad E–G (l1), F–G (l2) to the frame pivot F; the
                           path point P = E + (px + i·py)·(G − E)/l1 on the link E G
``watt_sixbar``            the same parameters, E = D + (ex + i·ey)·(C − D)/c on the rocker: a
                           Watt II six-bar (two four-bars in series)
``sixbar_slider``          Ax Ay Dx Dy a b c ex ey Fx Fy l1 g px py — the Stephenson III six-bar
                           whose second dyad is an RRP: the rod E–G (l1) drives a slider whose
                           pin G moves on the fixed guide {F + s·e^{ig}} (F a point of the
                           guide, g its direction, rad); P = E + (px + i·py)·(G − E)/l1 on the
                           rod; the output is the slider's position s (mm from F)
``watt_sixbar_slider``     the same, E on the rocker (as ``watt_sixbar``): a Watt II six-bar
                           with a slider
``sixbar_guide``           Ax Ay Dx Dy a b c ex ey Fx Fy e px py — the Stephenson III six-bar
                           whose second dyad is an RPR: a block pivoted at E slides on a guide
                           of the rocker pivoted at F, the guide at offset e from F (u: its
                           direction, as the inverted slider-crank's); the block carries
                           P = E + (px + i·py)·u; the output is the guided rocker's angle
``watt_sixbar_guide``      the same, E on the rocker: a Watt II six-bar with a guided rocker
=========================  =====================================================================

plus an assembly mode σ = ±1 per design (which of the two closures); the six-bar's code
σ ∈ {±1, ±2} gives both of its groups' modes: σ1 = sign σ, σ2 = σ1 when |σ| = 1, else −σ1 (so
that −σ is the mirror image's). The crank angle θ (rad,
world frame, of A→B) is per sample. :func:`evaluate` gives the coupler point P (complex, mm),
the output (a rocker's angle, rad; a slider's position along its line, mm), the sine of the
transmission angle, and, with ``grad``, ∂P/∂(parameters, θ) and ∂output/∂(...) from
:class:`~.dual.Dual` (the same closed forms differentiated: exact to rounding). NaN marks samples
that cannot be assembled. The product's solver is the reference: the tests compare P and the
output with ``compile_plan(...).evaluate`` of the linkage :mod:`.candidates` builds.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .dual import Dual

FOURBAR, SLIDER_CRANK, INVERTED, SIXBAR = "fourbar", "slider_crank", "inverted_slider_crank", "sixbar"
WATT = "watt_sixbar"
SIXBAR_SLIDER, WATT_SLIDER = "sixbar_slider", "watt_sixbar_slider"
#: the six-bars with an RRR second dyad (the same parameters; E on the connector: Stephenson
#: III; on the rocker: Watt II)
SIXBARS = (SIXBAR, WATT)
#: the six-bars whose second dyad is an RRP (a slider on a fixed guide)
SLIDER_SIXBARS = (SIXBAR_SLIDER, WATT_SLIDER)
SIXBAR_GUIDE, WATT_GUIDE = "sixbar_guide", "watt_sixbar_guide"
#: the six-bars whose second dyad is an RPR (a block on a guide of a rocker pivoted at F)
GUIDE_SIXBARS = (SIXBAR_GUIDE, WATT_GUIDE)
#: every six-bar: the first dyad RRR, E on the connector or the rocker, the second RRR, RRP or
#: RPR; all share the layout A, D, a, b, c, ex, ey, F (9, 10), then l1 (11) and l2 or g, or the
#: guide's offset e (11), then px, py
ALL_SIXBARS = SIXBARS + SLIDER_SIXBARS + GUIDE_SIXBARS
#: the six-bars with E on the rocker (Watt II)
WATTS = (WATT, WATT_SLIDER, WATT_GUIDE)

PARAMS: dict[str, tuple[str, ...]] = {
    FOURBAR: ("Ax", "Ay", "Dx", "Dy", "a", "b", "c", "px", "py"),
    SLIDER_CRANK: ("Ax", "Ay", "g", "h", "a", "b", "px", "py"),
    INVERTED: ("Ax", "Ay", "Gx", "Gy", "a", "e", "px", "py"),
    SIXBAR: ("Ax", "Ay", "Dx", "Dy", "a", "b", "c", "ex", "ey", "Fx", "Fy", "l1", "l2", "px", "py"),
    WATT: ("Ax", "Ay", "Dx", "Dy", "a", "b", "c", "ex", "ey", "Fx", "Fy", "l1", "l2", "px", "py"),
    SIXBAR_SLIDER: ("Ax", "Ay", "Dx", "Dy", "a", "b", "c", "ex", "ey", "Fx", "Fy", "l1", "g", "px", "py"),
    WATT_SLIDER: ("Ax", "Ay", "Dx", "Dy", "a", "b", "c", "ex", "ey", "Fx", "Fy", "l1", "g", "px", "py"),
    SIXBAR_GUIDE: ("Ax", "Ay", "Dx", "Dy", "a", "b", "c", "ex", "ey", "Fx", "Fy", "e", "px", "py"),
    WATT_GUIDE: ("Ax", "Ay", "Dx", "Dy", "a", "b", "c", "ex", "ey", "Fx", "Fy", "e", "px", "py"),
}
#: parameters that are lengths which must stay positive
POSITIVE: dict[str, tuple[str, ...]] = {FOURBAR: ("a", "b", "c"), SLIDER_CRANK: ("a", "b"), INVERTED: ("a",),
                                        SIXBAR: ("a", "b", "c", "l1", "l2"), WATT: ("a", "b", "c", "l1", "l2"),
                                        SIXBAR_SLIDER: ("a", "b", "c", "l1"), WATT_SLIDER: ("a", "b", "c", "l1"),
                                        SIXBAR_GUIDE: ("a", "b", "c"), WATT_GUIDE: ("a", "b", "c")}
#: the output's unit per topology (rocker angle or slider position)
OUTPUT_UNIT = {FOURBAR: "rad", SLIDER_CRANK: "mm", INVERTED: "rad", SIXBAR: "rad", WATT: "rad", SIXBAR_SLIDER: "mm",
               WATT_SLIDER: "mm", SIXBAR_GUIDE: "rad", WATT_GUIDE: "rad"}
TOPOLOGIES = tuple(PARAMS)


@dataclass
class Evaluation:
    """Closed-form kinematics of D designs at N samples each.

    ``P`` (D, N) complex mm; ``out`` (D, N) float (rad or mm); ``cpl`` (D, N) the coupler's
    angle, rad (of B→C; the inverted slider-crank's block: of its guide u); ``sin_mu`` (D, N)
    the sine of the transmission angle (0 at a dead point); ``joints`` name -> (D, N) complex
    (B, C, ...); ``dP``, ``dout``, ``dcpl`` (D, N, K + 1) the derivatives with respect to the K
    parameters and, last, the crank angle θ (None without ``grad``); ``ok`` (D, N) assembled."""

    P: np.ndarray
    out: np.ndarray
    cpl: np.ndarray
    sin_mu: np.ndarray
    joints: dict[str, np.ndarray]
    ok: np.ndarray
    dP: np.ndarray | None = None
    dout: np.ndarray | None = None
    dcpl: np.ndarray | None = None
    dsin_mu: np.ndarray | None = None


def _val(x: Any) -> np.ndarray:
    return x.v if isinstance(x, Dual) else x


def _sqrt(x):
    if isinstance(x, Dual):
        return x.sqrt()
    with np.errstate(invalid="ignore"):
        return np.sqrt(x)


def _expi(x):
    return x.expi() if isinstance(x, Dual) else np.exp(1j * x)


def _abs2(z):
    return z.abs2() if isinstance(z, Dual) else z.real ** 2 + z.imag ** 2


def _conj(z):
    return z.conj() if isinstance(z, Dual) else np.conj(z)


def _re(z):
    return z.real if isinstance(z, Dual) else np.real(z)


def _im(z):
    return z.imag if isinstance(z, Dual) else np.imag(z)


def _abs(x):
    return x.abs() if isinstance(x, Dual) else np.abs(x)


def _angle(z):
    return z.angle() if isinstance(z, Dual) else np.angle(z)


def _fourbar(p: list, th, sigma: np.ndarray) -> tuple:
    ax, ay, dx, dy, a, b, c, px, py = p
    A, D = ax + 1j * ay, dx + 1j * dy
    B = A + a * _expi(th)
    d = D - B
    L2 = _abs2(d)
    x = (b * b - c * c + L2) / (2.0 * L2)
    h = _sqrt(b * b / L2 - x * x)
    C = B + d * (x + 1j * sigma * h)
    P = B + (px + 1j * py) * (C - B) / b
    out = _angle(C - D)
    sin_mu = _abs(_im(_conj(C - B) * (C - D)) / (b * c))
    return P, out, _angle(C - B), sin_mu, {"A": _val(A), "B": _val(B), "C": _val(C), "D": _val(D)}


def _slider_crank(p: list, th, sigma: np.ndarray) -> tuple:
    ax, ay, g, h, a, b, px, py = p
    A = ax + 1j * ay
    e = _expi(g)
    B = A + a * _expi(th)
    Bl = _conj(e) * (B - A)
    q = _sqrt(b * b - (h - _im(Bl)) * (h - _im(Bl)))
    s = _re(Bl) + sigma * q
    C = A + (s + 1j * h) * e
    P = B + (px + 1j * py) * (C - B) / b
    sin_mu = _abs(q / b)
    return P, s, _angle(C - B), sin_mu, {"A": _val(A), "B": _val(B), "C": _val(C), "e": _val(e)}


def _inverted(p: list, th, sigma: np.ndarray) -> tuple:
    ax, ay, gx, gy, a, e, px, py = p
    A, G = ax + 1j * ay, gx + 1j * gy
    B = A + a * _expi(th)
    r = B - G
    r2 = _abs2(r)
    t = sigma * _sqrt(r2 - e * e)
    u = r * (t - 1j * e) / r2
    P = B + (px + 1j * py) * u
    out = _angle(u)
    sin_mu = _abs(t / _sqrt(r2))
    return P, out, out, sin_mu, {"A": _val(A), "B": _val(B), "G": _val(G), "u": _val(u)}


def _rrr(M, H, li, lj, sigma):
    """The inner joint of an RRR dyad on outer joints M, H with link lengths li (from M), lj."""
    d = H - M
    L2 = _abs2(d)
    x = (li * li - lj * lj + L2) / (2.0 * L2)
    h = _sqrt(li * li / L2 - x * x)
    return M + d * (x + 1j * sigma * h)


def _first_loop(p: list, th, sigma: np.ndarray, watt: bool) -> tuple:
    """The four-bar loop A B C D every six-bar family starts with (p's first eleven entries: A, D,
    crank a, coupler b, rocker c, E's offset on the coupler (Stephenson) or the rocker (Watt), F),
    at crank angles th (rad): the two dyads' assembly signs s1, s2 from sigma and the points A, B,
    C, D, E, F as complex numbers (mm)."""
    ax, ay, dx, dy, a, b, c, ex, ey, fx, fy = p[:11]
    s1 = np.sign(sigma)
    s2 = np.where(np.abs(sigma) < 1.5, s1, -s1)
    A, D, Fp = ax + 1j * ay, dx + 1j * dy, fx + 1j * fy
    B = A + a * _expi(th)
    C = _rrr(B, D, b, c, s1)
    E = D + (ex + 1j * ey) * (C - D) / c if watt else B + (ex + 1j * ey) * (C - B) / b
    return s1, s2, A, B, C, D, E, Fp


def _sixbar(p: list, th, sigma: np.ndarray, watt: bool = False) -> tuple:
    ax, ay, dx, dy, a, b, c, ex, ey, fx, fy, l1, l2, px, py = p
    s1, s2, A, B, C, D, E, Fp = _first_loop(p, th, sigma, watt)
    G = _rrr(E, Fp, l1, l2, s2)
    P = E + (px + 1j * py) * (G - E) / l1
    mu1 = _abs(_im(_conj(C - B) * (C - D)) / (b * c))
    mu2 = _abs(_im(_conj(G - E) * (G - Fp)) / (l1 * l2))
    sin_mu = _lesser(mu1, mu2)
    joints = {"A": _val(A), "B": _val(B), "C": _val(C), "D": _val(D), "E": _val(E), "F": _val(Fp), "G": _val(G)}
    return P, _angle(G - Fp), _angle(G - E), sin_mu, joints


def _watt(p: list, th, sigma: np.ndarray) -> tuple:
    return _sixbar(p, th, sigma, watt=True)


def _lesser(m1, m2):
    """The smaller of two (Dual) sines of transmission angles, element by element."""
    if isinstance(m1, Dual):
        take = _val(m1) <= _val(m2)
        return Dual(np.where(take, m1.v, m2.v), np.where(take[..., None], m1.d, m2.d))
    return np.minimum(m1, m2)


def _sixbar_slider(p: list, th, sigma: np.ndarray, watt: bool = False) -> tuple:
    """The six-bar with an RRP second dyad (:data:`SLIDER_SIXBARS`): the rod E–G and the slider
    pin G on the fixed guide through F at angle g; its transmission quality is |cos| of the
    rod's angle to the guide's normal (the pressure angle's cosine), q / l1."""
    ax, ay, dx, dy, a, b, c, ex, ey, fx, fy, l1, g, px, py = p
    s1, s2, A, B, C, D, E, Fp = _first_loop(p, th, sigma, watt)
    e = _expi(g)
    El = _conj(e) * (E - Fp)
    q = _sqrt(l1 * l1 - _im(El) * _im(El))
    s = _re(El) + s2 * q
    G = Fp + s * e
    P = E + (px + 1j * py) * (G - E) / l1
    mu1 = _abs(_im(_conj(C - B) * (C - D)) / (b * c))
    sin_mu = _lesser(mu1, _abs(q / l1))
    joints = {"A": _val(A), "B": _val(B), "C": _val(C), "D": _val(D), "E": _val(E), "F": _val(Fp), "G": _val(G),
              "e": _val(e)}
    return P, s, _angle(G - E), sin_mu, joints


def _watt_slider(p: list, th, sigma: np.ndarray) -> tuple:
    return _sixbar_slider(p, th, sigma, watt=True)


def _sixbar_guide(p: list, th, sigma: np.ndarray, watt: bool = False) -> tuple:
    """The six-bar with an RPR second dyad (:data:`GUIDE_SIXBARS`): the block pivoted at E on
    the guide of the rocker pivoted at F (offset e), as the inverted slider-crank's; its
    transmission quality is t/|E − F|, the cosine of the guide's angle to the line F E's normal."""
    ax, ay, dx, dy, a, b, c, ex, ey, fx, fy, e, px, py = p
    s1, s2, A, B, C, D, E, Fp = _first_loop(p, th, sigma, watt)
    r = E - Fp
    r2 = _abs2(r)
    t = s2 * _sqrt(r2 - e * e)
    u = r * (t - 1j * e) / r2
    P = E + (px + 1j * py) * u
    mu1 = _abs(_im(_conj(C - B) * (C - D)) / (b * c))
    sin_mu = _lesser(mu1, _abs(t / _sqrt(r2)))
    out = _angle(u)
    joints = {"A": _val(A), "B": _val(B), "C": _val(C), "D": _val(D), "E": _val(E), "F": _val(Fp), "u": _val(u)}
    return P, out, out, sin_mu, joints


def _watt_guide(p: list, th, sigma: np.ndarray) -> tuple:
    return _sixbar_guide(p, th, sigma, watt=True)


_EVAL = {FOURBAR: _fourbar, SLIDER_CRANK: _slider_crank, INVERTED: _inverted, SIXBAR: _sixbar, WATT: _watt,
         SIXBAR_SLIDER: _sixbar_slider, WATT_SLIDER: _watt_slider, SIXBAR_GUIDE: _sixbar_guide,
         WATT_GUIDE: _watt_guide}


def evaluate(topology: str, x: np.ndarray, theta: np.ndarray, sigma=1.0, grad: bool = False) -> Evaluation:
    """Kinematics of designs ``x`` (D, K) at crank angles ``theta`` (D, N) rad (world frame), in
    assembly modes ``sigma`` (scalar or (D,) of ±1). See the module docstring."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    th = np.asarray(theta, dtype=float)
    if th.ndim == 1:
        th = np.broadcast_to(th, (x.shape[0], th.shape[0]))
    sig = np.broadcast_to(np.asarray(sigma, dtype=float).reshape(-1, 1), (x.shape[0], 1))
    k = x.shape[1]
    if k != len(PARAMS[topology]):
        raise ValueError(f"{topology}: {len(PARAMS[topology])} parameters expected, got {k}")
    if grad:
        cols = [Dual.seed(x[:, j:j + 1], j, k + 1) for j in range(k)]
        thd = Dual(th, np.zeros(th.shape + (k + 1,)))
        thd.d[..., k] = 1.0
    else:
        cols, thd = [x[:, j:j + 1] for j in range(k)], th
    with np.errstate(invalid="ignore", divide="ignore"):
        P, out, cpl, sin_mu, joints = _EVAL[topology](cols, thd, sig)
    Pv, ov, cv, sv = _val(P), _val(out), _val(cpl), _val(sin_mu)
    ok = np.isfinite(Pv) & np.isfinite(ov)
    shape = Pv.shape
    if not grad:
        return Evaluation(Pv, np.broadcast_to(ov, shape), np.broadcast_to(cv, shape), sv, joints, ok)
    full = shape + (k + 1,)
    return Evaluation(Pv, np.broadcast_to(ov, shape), np.broadcast_to(cv, shape), sv, joints, ok, P.d,
                      np.broadcast_to(out.d, full), np.broadcast_to(cpl.d, full), np.broadcast_to(sin_mu.d, full))


def transform(topology: str, x: np.ndarray, s: complex | np.ndarray, t: complex | np.ndarray) -> np.ndarray:
    """Designs ``x`` (D, K) moved by the similarity z → s·z + t (s complex: scale |s| and turn
    arg s; scalars or (D,)): the moved design traces s·P + t at crank angle θ + arg s."""
    x = np.array(x, dtype=float)
    s = np.broadcast_to(np.asarray(s, dtype=complex), x.shape[:1])
    t = np.broadcast_to(np.asarray(t, dtype=complex), x.shape[:1])
    k, turn = np.abs(s), np.angle(s)
    A = s * (x[:, 0] + 1j * x[:, 1]) + t
    x[:, 0], x[:, 1] = A.real, A.imag
    if topology == SLIDER_CRANK:
        x[:, 2] += turn
        x[:, 3:] *= k[:, None]
    elif topology in ALL_SIXBARS:
        for i in (2, 9):
            Z = s * (x[:, i] + 1j * x[:, i + 1]) + t
            x[:, i], x[:, i + 1] = Z.real, Z.imag
        for i in range(4, x.shape[1]):
            if i in (9, 10):                 # F, moved above
                continue
            if i == 12 and topology in SLIDER_SIXBARS:
                x[:, i] += turn          # the guide's direction turns
            else:
                x[:, i] *= k
    else:
        G = s * (x[:, 2] + 1j * x[:, 3]) + t
        x[:, 2], x[:, 3] = G.real, G.imag
        x[:, 4:] *= k[:, None]
    return x


def mirror(topology: str, x: np.ndarray, sigma) -> tuple[np.ndarray, np.ndarray]:
    """The mirror images of designs ``x`` (D, K) in the x axis and their modes: the mirrored
    design traces conj(P) at crank angle −θ."""
    x = np.array(x, dtype=float)
    x[:, 1] = -x[:, 1]
    x[:, -1] = -x[:, -1]
    sig = np.asarray(sigma, dtype=float)
    if topology == SLIDER_CRANK:
        x[:, 2], x[:, 3] = -x[:, 2], -x[:, 3]
        return x, sig
    x[:, 3] = -x[:, 3]
    if topology in SIXBARS:
        x[:, 8], x[:, 10] = -x[:, 8], -x[:, 10]
        return x, -sig
    if topology in SLIDER_SIXBARS:   # the rod's mode keeps its sign (s is measured along the guide)
        x[:, 8], x[:, 10], x[:, 12] = -x[:, 8], -x[:, 10], -x[:, 12]
        return x, -np.sign(sig) * (3.0 - np.abs(sig))
    if topology in GUIDE_SIXBARS:    # the guide's offset changes sign, the block's mode does not
        x[:, 8], x[:, 10], x[:, 11] = -x[:, 8], -x[:, 10], -x[:, 11]
        return x, -np.sign(sig) * (3.0 - np.abs(sig))
    if topology == INVERTED:
        x[:, 5] = -x[:, 5]
        return x, sig
    return x, -sig


__all__ = ["ALL_SIXBARS", "Evaluation", "FOURBAR", "GUIDE_SIXBARS", "INVERTED", "OUTPUT_UNIT", "PARAMS", "POSITIVE",
           "SIXBAR", "SIXBARS", "SIXBAR_GUIDE", "SIXBAR_SLIDER", "SLIDER_CRANK", "SLIDER_SIXBARS", "TOPOLOGIES", "WATT",
           "WATTS", "WATT_GUIDE", "WATT_SLIDER", "evaluate", "mirror", "transform"]
