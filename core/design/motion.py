"""Motion synthesis (rigid-body guidance): four-bars whose coupler passes through given poses.

3 and 4 poses are solved exactly with Burmester theory (:mod:`.burmester`): every pair of
dyads (circle point, centre point) is a four-bar whose coupler takes every pose, provided the
four-bar reaches them on one circuit (no circuit or branch defect), in the given order (no order
defect) and without a dead point between them; pairs are screened for these defects in closed
form over all pairs at once, ranked by their least transmission angle over the span (a fully
turning crank first when asked), and the best are built and driven by the product's solver
(:func:`~.finish.finish`). With 5 or more poses, least-squares circle points give the starting
pairs, which Levenberg–Marquardt refines on the poses' position and angle errors.

``synthesize_motion(target, options, progress)`` returns a :class:`~.options.DesignResult`;
each candidate's joint ``P`` on link ``coupler`` carries the poses (its position is the poses'
point, the coupler's turn from pose 1 is the poses' turn).
"""
from __future__ import annotations

import math

import numpy as np

from ..solver.plan import Plan
from . import burmester as BM
from . import families as F
from .candidates import Stopwatch
from .finish import Design, finish, refusal_text, relax_text
from .options import DesignResult, LinkageOptions
from .refine import levenberg_marquardt
from .targets import DesignError, PoseTarget, Progress, report

#: circle points per side of the grid (3 poses; 5+ poses before fitting)
GRID = 21
#: most dyads paired (all ordered pairs are screened)
MAX_DYADS = 200
#: dense samples of the screen between the first and the last pose
SPAN_SAMPLES = 24
#: an exact pose is met to this fraction of the size (else the pair has a circuit defect)
EXACT_REL = 1e-7


def _wrap(a: np.ndarray) -> np.ndarray:
    return np.remainder(a + math.pi, 2 * math.pi) - math.pi


def _grid(target: PoseTarget, side: int, region: tuple[float, float, float, float] | None = None,
          reach: float = 1.5) -> np.ndarray:
    """Points on a square grid (complex): around the poses (± ``reach`` sizes), or over
    ``region`` (xmin, ymin, xmax, ymax) clipped to ±5 sizes of them."""
    c = complex(*target.points.mean(axis=0))
    h = reach * target.size
    x0, y0, x1, y1 = c.real - h, c.imag - h, c.real + h, c.imag + h
    if region is not None:
        w = 5.0 * target.size
        x0, y0 = max(region[0], c.real - w), max(region[1], c.imag - w)
        x1, y1 = min(region[2], c.real + w), min(region[3], c.imag + w)
        if not (x0 < x1 and y0 < y1):
            return np.empty(0, dtype=complex)
    u, v = np.linspace(x0, x1, side), np.linspace(y0, y1, side)
    return (u[None, :] + 1j * v[:, None]).reshape(-1)


def _dyads(target: PoseTarget, options: LinkageOptions) -> tuple[np.ndarray, np.ndarray]:
    """Circle points and centre points to pair (at most MAX_DYADS, spread along their sets):
    circle points on a grid and their centres, and centres on a grid (over the pivot region when
    one is given) and their circle points."""
    n = len(target.points)
    size, centre = target.size, complex(*target.points.mean(axis=0))
    region = options.pivot_region
    if n == 3:
        m1 = _grid(target, GRID)
        g2 = _grid(target, GRID, region, 2.0)
        m = np.concatenate([m1, BM.circle_points(target, g2)])
        g = np.concatenate([BM.circle_centres(target, m1), g2])
    elif n == 4:
        m, g, _ = BM.four_pose_dyads(target, 3600 if region is None else 36000)
    else:
        m1 = _grid(target, 2 * GRID)
        g1, _, r1 = BM.fit_centres(target, m1)
        g2 = _grid(target, 2 * GRID, region, 2.0)
        m2, _, r2 = BM.fit_circles(BM.inverse_positions(target, g2))   # circle points of grid centres
        m, g, res = np.concatenate([m1, g2]), np.concatenate([g1, m2]), np.concatenate([r1, r2])
        keep = np.argsort(np.where(np.isfinite(res), res, np.inf))[: 4 * MAX_DYADS]
        m, g = m[keep], g[keep]
    r = np.abs(m - g)
    ok = np.isfinite(g) & np.isfinite(m) & (r >= 0.02 * size) & (r <= options.max_size * size)
    ok &= options.pivot_ok(g, centre, size)
    m, g = m[ok], g[ok]
    if len(m) > MAX_DYADS:
        pick = np.linspace(0, len(m) - 1, MAX_DYADS).round().astype(int)
        m, g = m[pick], g[pick]
    return m, g


def _pair_designs(target: PoseTarget, m: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """All ordered pairs (crank dyad i, rocker dyad j): four-bar parameters (D, 9), modes (D,)
    and crank angles at the poses (D, n)."""
    i, j = np.nonzero(~np.eye(len(m), dtype=bool))
    A, B, Dp, C = g[i], m[i], g[j], m[j]
    P1 = target.complex_points[0]
    b = np.abs(C - B)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = (P1 - B) * b / (C - B)
    x = np.stack([A.real, A.imag, Dp.real, Dp.imag, np.abs(B - A), b, np.abs(C - Dp), p.real, p.imag], axis=1)
    sigma = np.sign(np.imag(np.conj(Dp - B) * (C - B)))
    theta = np.angle(BM.positions(target, B) - A[:, None])
    return x, sigma, theta


def _order_direction(theta: np.ndarray) -> np.ndarray:
    """(D,) +1 or −1 when the poses are met in order turning the crank that way, else 0."""
    out = np.zeros(theta.shape[0])
    for sgn in (1.0, -1.0):
        off = np.remainder(sgn * (theta - theta[:, :1]), 2 * math.pi)[:, 1:]
        inc = np.all(np.diff(off, axis=1) > 0, axis=1) & np.all(off > 0, axis=1)
        out[(out == 0) & inc] = sgn
    return out


def _span_screen(x, sigma, theta, direction) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(min sin μ over the span (D,), assembled over the span (D,), crank turns fully (D,))."""
    off = np.remainder(direction[:, None] * (theta[:, -1:] - theta[:, :1]), 2 * math.pi)
    s = np.linspace(0.0, 1.0, SPAN_SAMPLES)[None, :]
    th = theta[:, :1] + direction[:, None] * off * s
    ev = F.evaluate(F.FOURBAR, x, th, sigma)
    ok = ev.ok.all(axis=1)
    mu = np.where(ev.ok, ev.sin_mu, 0.0).min(axis=1)
    full = F.evaluate(F.FOURBAR, x, theta[:, :1] + np.linspace(0, 2 * math.pi, 37)[None, :], sigma)
    return mu, ok, (full.ok & (full.sin_mu > 1e-6)).all(axis=1)


def _pose_errors(target: PoseTarget, x, sigma, theta) -> tuple[np.ndarray, np.ndarray]:
    """(largest position error (D,) mm, largest turn error (D,) rad) at crank angles theta."""
    ev = F.evaluate(F.FOURBAR, x, theta, sigma)
    pos = np.abs(ev.P - target.complex_points[None, :]).max(axis=1)
    turn = (ev.cpl - ev.cpl[:, :1]) - (target.angles_rad - target.angles_rad[0])[None, :]
    return np.where(np.isfinite(pos), pos, np.inf), np.abs(_wrap(turn)).max(axis=1)


def _refine(target: PoseTarget, x, sigma, theta, stop) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Levenberg–Marquardt on the poses' position (/size) and angle errors over the four-bar's
    parameters, its coupler's angle offset κ and the crank angle at each pose."""
    n, size = len(target.points), target.size
    P, phi = target.complex_points, target.angles_rad
    ev0 = F.evaluate(F.FOURBAR, x, theta[:, :1], sigma)
    kappa = phi[0] - ev0.cpl[:, 0]
    u0 = np.concatenate([x, kappa[:, None], theta], axis=1)

    def fun(u, rows):
        ev = F.evaluate(F.FOURBAR, u[:, :9], u[:, 10:], sigma[rows], grad=True)
        D = len(u)
        r = np.concatenate([(ev.P - P).real / size, (ev.P - P).imag / size,
                            _wrap(ev.cpl + u[:, 9:10] - phi)], axis=1)
        J = np.zeros((D, 3 * n, 10 + n))
        for k in range(n):
            J[:, k, :9] = ev.dP[:, k, :9].real / size
            J[:, n + k, :9] = ev.dP[:, k, :9].imag / size
            J[:, 2 * n + k, :9] = ev.dcpl[:, k, :9]
            J[:, k, 10 + k] = ev.dP[:, k, 9].real / size
            J[:, n + k, 10 + k] = ev.dP[:, k, 9].imag / size
            J[:, 2 * n + k, 10 + k] = ev.dcpl[:, k, 9]
            J[:, 2 * n + k, 9] = 1.0
        return r, J

    u, _ = levenberg_marquardt(fun, u0, iterations=80, stop=stop)
    return u[:, :9], u[:, 10:], u[:, 9]


def _ranked(target: PoseTarget, options: LinkageOptions, notes: list[str], progress: Progress | None) -> list[Design]:
    """Dyad pairs without circuit, branch or order defects, ranked (exact for 3 and 4 poses, refined
    by least squares for more)."""
    n, size = len(target.points), target.size
    report(progress, 0.0, "circle and centre points")
    m, g = _dyads(target, options)
    if len(m) < 2:
        raise DesignError("motion: no usable dyad (every centre point lies outside the pivot region or too far "
                          "away); widen the pivot region or raise the size limit")
    x, sigma, theta = _pair_designs(target, m, g)
    report(progress, 0.2, f"screening {len(x)} dyad pairs")
    ok = np.all(np.isfinite(x), axis=1) & (sigma != 0) & (np.abs(x[:, 5]) >= 0.05 * size)
    ok &= np.abs((x[:, 0] - x[:, 2]) + 1j * (x[:, 1] - x[:, 3])) >= 0.05 * size
    x, sigma, theta = x[ok], sigma[ok], theta[ok]
    pos, turn = _pose_errors(target, x, sigma, theta)
    notes.append(f"{len(m)} dyads, {len(x)} pairs screened")
    if n >= 5:
        best = np.argsort(pos / size + turn)[:192]
        x, sigma, theta = x[best], sigma[best], theta[best]
        report(progress, 0.4, f"least squares on {len(x)} pairs")
        x, theta, _ = _refine(target, x, sigma, theta, lambda: report(progress, 0.5, "least squares"))
        pos, turn = _pose_errors(target, x, sigma, theta)
        exact = np.isfinite(pos)
    else:
        exact = (pos <= EXACT_REL * size) & (turn <= 1e-7)
    circuit = int((~exact).sum())
    x, sigma, theta, pos, turn = x[exact], sigma[exact], theta[exact], pos[exact], turn[exact]
    direction = _order_direction(theta)
    order = int((direction == 0).sum())
    keep = direction != 0
    x, sigma, theta, direction, pos, turn = x[keep], sigma[keep], theta[keep], direction[keep], pos[keep], turn[keep]
    report(progress, 0.6, f"transmission angles of {len(x)} defect-free pairs")
    mu, span_ok, full = _span_screen(x, sigma, theta, direction) if len(x) else \
        (np.empty(0), np.zeros(0, bool), np.zeros(0, bool))
    mu_deg = np.degrees(np.arcsin(np.clip(mu, 0.0, 1.0)))
    good = span_ok & (mu_deg >= options.min_transmission_deg)
    if options.full_turn:
        good &= full
    notes.append(f"{circuit} with a circuit or branch defect, {order} with an order defect, "
                 f"{int((~good).sum())} with a dead point or a transmission angle below {options.min_transmission_deg:g}°")
    score = mu_deg + 20.0 * full - 100.0 * np.log10(1.0 + (pos / size + turn) / 1e-6) * (n >= 5)
    rank = np.flatnonzero(good)[np.argsort(-score[good])]
    return [Design(F.FOURBAR, x[k], float(sigma[k]), float(direction[k]), theta[k], float(score[k])) for k in rank]


def synthesize_motion(target: PoseTarget, options: LinkageOptions = LinkageOptions(),
                      progress: Progress | None = None) -> DesignResult:
    """Four-bars whose coupler carries joint ``P`` through the poses (see the module docstring).
    Raises DesignError saying what to relax when no defect-free four-bar is found."""
    options.check()
    watch = Stopwatch()
    notes: list[str] = []
    designs = _ranked(target, options, notes, progress)

    def measure(plan: Plan, d: Design):
        sol = plan.evaluate(d.inputs, order=0, joints=["P"])
        p = sol.position("P")
        dev = float(np.max(np.hypot(p[:, 0] - target.points[:, 0], p[:, 1] - target.points[:, 1])))
        rot = sol.angle("coupler")
        adev = float(np.max(np.abs(_wrap((rot - rot[0]) - (target.angles_rad - target.angles_rad[0])))))
        return dev, "mm", math.degrees(adev), None

    found, refused = finish(designs, options, target.size, False, measure, progress=progress)
    if not found:
        raise DesignError(f"motion: no defect-free four-bar guides the body through the {len(target.points)} poses ("
                          + "; ".join(notes) + (f"; built and refused: {refusal_text(refused)}" if refused else "")
                          + "): " + relax_text(refused, "lower the minimum transmission angle, widen the pivot "
                                                          "region or move the poses"))
    if refused:
        notes.append(f"refused after building: {refusal_text(refused)}")
    report(progress, 1.0, "done")
    return DesignResult(found, watch.elapsed, notes)


__all__ = ["synthesize_motion"]
