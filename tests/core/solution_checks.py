"""Checks of a linkage Solution from its public API only, independent of the solver's formulas:

* :func:`closure_error` — loop closure (every link rigid, not mirrored, every R joint shared,
  every P joint a pure slide along its axis, the ground fixed, the driver at its input);
* :func:`fd_check`, :func:`fd_errors` — the solver's velocities and accelerations against
  finite differences of its own positions and velocities;
* :func:`mode_signs`, :func:`link_rotation` — assembly-mode invariants and rotations from
  positions, used by several test files.
"""
from __future__ import annotations

import math

import numpy as np

from linkage_builders import e, size_of
from mechsketch.core import JointKind, Linkage

R = JointKind.R


# ---------------------------------------------------------------------------------------------
# loop closure from the public Solution API
# ---------------------------------------------------------------------------------------------
def _frames(linkage: Linkage, sol, scale: float):
    """Per link: origin point, x-probe and y-probe positions (complex (N,)), from sol.point."""
    out = {}
    for lk in linkage.links:
        c = linkage.joint(lk.joints[0]).at
        p = sol.point(lk.id, c)
        px = sol.point(lk.id, (c[0] + scale, c[1]))
        py = sol.point(lk.id, (c[0], c[1] + scale))
        z = lambda a: a[:, 0] + 1j * a[:, 1]  # noqa: E731
        out[lk.id] = (z(p), z(px), z(py), c)
    return out


def closure_error(linkage: Linkage, sol, mask=None) -> float:
    """Largest violation (mm) of the linkage's constraints over the samples in ``mask`` (default:
    ``sol.valid``), computed only from ``sol.point``/``sol.position``."""
    scale = size_of(linkage)
    mask = sol.valid if mask is None else mask
    fr = _frames(linkage, sol, scale)
    worst = 0.0

    def upd(v):
        nonlocal worst
        v = np.abs(v)[mask]
        if v.size:
            m = float(np.max(v))
            worst = max(worst, m if np.isfinite(m) else math.inf)

    rot = {}
    for k, (p, px, py, c) in fr.items():
        upd(np.abs(px - p) - scale)                 # rigid
        upd(np.abs(py - p) - scale)
        upd((py - p) - 1j * (px - p))               # not mirrored, not sheared
        rot[k] = (px - p) / scale
        pts = {j: sol.point(k, linkage.joint(j).at) for j in linkage.link(k).joints}
        for a in pts:
            for b in pts:
                da = complex(*linkage.joint(a).at) - complex(*linkage.joint(b).at)
                dd = (pts[a][:, 0] - pts[b][:, 0]) + 1j * (pts[a][:, 1] - pts[b][:, 1])
                upd(dd - rot[k] * da)
    for j in linkage.joints:
        carriers = linkage.links_of(j.id)
        pts = [sol.point(k, j.at) for k in carriers]
        pts = [a[:, 0] + 1j * a[:, 1] for a in pts]
        if j.kind is R:
            for q in pts[1:]:
                upd(q - pts[0])
        else:
            a, b = carriers
            upd(scale * (rot[a] - rot[b]))
            u = rot[a] * e(j.axis_deg)
            upd(cross2_arr(u, pts[1] - pts[0]))
    # the ground does not move; the driver turns about its pivot by the input (a crank), its end
    # pivots are the input apart (a cylinder), or it slides along its guide by the input (a slider)
    g = fr[linkage.ground]
    upd(g[0] - complex(*g[3]))
    upd(rot[linkage.ground] - 1)
    drv = linkage.driver
    if drv.kind == "cylinder":
        rod = next(k for k in linkage.links_of(drv.pivot) if k != drv.link)
        m = next(x for x in linkage.link(drv.link).joints if x != drv.pivot)
        h = next(x for x in linkage.link(rod).joints if x != drv.pivot)
        pm, ph = sol.point(drv.link, linkage.joint(m).at), sol.point(rod, linkage.joint(h).at)
        upd(np.hypot(*(ph - pm).T) - sol.input)
        return worst
    if drv.kind == "slider":
        s0 = complex(*linkage.joint(drv.pivot).at)
        ps = sol.point(drv.link, linkage.joint(drv.pivot).at)
        upd((ps[:, 0] + 1j * ps[:, 1] - s0) - sol.input * e(linkage.joint(drv.pivot).axis_deg))
        upd(scale * (rot[drv.link] - 1))
        return worst
    pv = complex(*linkage.joint(drv.pivot).at)
    tip = next(x for x in linkage.link(drv.link).joints if x != drv.pivot)
    t0 = complex(*linkage.joint(tip).at) - pv
    tp = sol.point(drv.link, linkage.joint(tip).at)
    tp = tp[:, 0] + 1j * tp[:, 1]
    upd(scale * (np.angle((tp - pv) / t0 * np.exp(-1j * (sol.input - math.atan2(t0.imag, t0.real))))))
    pp = sol.point(drv.link, linkage.joint(drv.pivot).at)
    upd(pp[:, 0] + 1j * pp[:, 1] - pv)
    return worst


def cross2_arr(a, b):
    return (np.conj(a) * b).imag


# ---------------------------------------------------------------------------------------------
# finite differences of the solver itself
# ---------------------------------------------------------------------------------------------
def fd_check(plan, inputs, h: float = 1e-4):
    """Central 5-point differences along the driver angle, for every link point of every joint.

    Returns (v_solver, v_fd, v_fd_half, a_solver, a_fd, a_fd_half) as complex arrays (M, N):
    FD of positions for velocities and of velocities for accelerations, at steps h and h/2 (their
    difference estimates the FD error)."""
    lk = plan.linkage
    w = plan.omega
    inputs = np.asarray(inputs, float)
    pts = [(k.id, lk.joint(j).at) for k in lk.links for j in k.joints]

    def z(a):
        return a[:, 0] + 1j * a[:, 1]

    def at(offsets, order):
        x = np.concatenate([inputs + o for o in offsets])
        s = plan.evaluate(x, order=order)
        n = len(inputs)
        res = []
        for link, p0 in pts:
            if order == 0:
                v = z(s.point(link, p0))
            else:
                v = z(s.point_velocity(link, p0))
            res.append(v.reshape(len(offsets), n))
        return np.array(res)  # (M, len(offsets), N)

    def d5(arr, hh):
        return (arr[:, 0] - 8 * arr[:, 1] + 8 * arr[:, 2] - arr[:, 3]) / (12 * hh)

    base = plan.evaluate(inputs, order=2)
    vs = np.array([z(base.point_velocity(k, p)) for k, p in pts])
    as_ = np.array([z(base.point_acceleration(k, p)) for k, p in pts])
    out = []
    for order in (0, 1):
        r = []
        for hh in (h, h / 2):
            arr = at([-2 * hh, -hh, hh, 2 * hh], order)
            r.append(d5(arr, hh) * w)
        out.append(r)
    return vs, out[0][0], out[0][1], as_, out[1][0], out[1][1]


# ---------------------------------------------------------------------------------------------
# assembly-mode invariants and check helpers used by several test files
# ---------------------------------------------------------------------------------------------
def _z(a: np.ndarray) -> np.ndarray:
    return a[:, 0] + 1j * a[:, 1]


def link_rotation(sol, linkage: Linkage, link: str) -> np.ndarray:
    """exp(i·rotation from the drawn pose) of ``link``, from two sol.point probes."""
    c = linkage.joint(linkage.link(link).joints[0]).at
    return _z(sol.point(link, (c[0] + 1.0, c[1]))) - _z(sol.point(link, c))


def mode_signs(linkage: Linkage, sol, group) -> np.ndarray:
    """(N,) sign of the group's assembly-mode invariant, from positions only (0 where undefined):
    RRR cross(H − M, L − M); RRP dot(u, L − M), u the guide direction; RPR dot(u, M − H).
    PRP and RPP have a single assembly: ones."""
    k = group.kind
    if k == "RRR":
        M, Lp = _z(sol.point(group.link_i, linkage.joint(group.outer_i).at)), _z(sol.position(group.inner))
        H = _z(sol.point(group.link_j, linkage.joint(group.outer_j).at))
        return np.sign(cross2_arr(H - M, Lp - M))
    if k == "RRP":
        M = _z(sol.point(group.link_i, linkage.joint(group.outer_i).at))
        Lp = _z(sol.point(group.link_i, linkage.joint(group.inner).at))
        u = link_rotation(sol, linkage, group.link_j) * e(linkage.joint(group.outer_j).axis_deg)
        return np.sign(((np.conj(u)) * (Lp - M)).real)
    if k == "RPR":
        M = _z(sol.point(group.link_i, linkage.joint(group.outer_i).at))
        H = _z(sol.point(group.link_j, linkage.joint(group.outer_j).at))
        u = link_rotation(sol, linkage, group.link_j) * e(linkage.joint(group.inner).axis_deg)
        return np.sign(((np.conj(u)) * (M - H)).real)
    return np.ones(len(sol))


def fd_errors(plan, inputs, h: float = 1e-4, cond_min: float = 1e-3):
    """Compare the solver's velocities/accelerations with 5-point differences of its positions /
    velocities at the given inputs. Returns (bad_v, bad_a, checked, sharp) where bad_* count
    samples whose error exceeds 1e-9 of the scale plus twice the FD error estimate, ``checked``
    the samples used (all stencil points valid, every group's conditioning > cond_min) and
    ``sharp`` those whose FD error estimate is below 1e-7 of the scale."""
    vs, v1, v2, as_, a1, a2 = fd_check(plan, inputs, h)
    sol = plan.evaluate(np.asarray(inputs, float), order=0)
    ok = np.isfinite(vs).all(axis=0) & np.isfinite(v1).all(axis=0) & np.isfinite(v2).all(axis=0)
    ok &= np.isfinite(a1).all(axis=0) & np.isfinite(a2).all(axis=0)
    for g in sol.groups:
        ok &= np.nan_to_num(sol.conditioning(g.name), nan=0.0) > cond_min
    if not ok.any():
        return 0, 0, 0, 0, {}
    vsc = np.max(np.abs(vs[:, ok]))
    asc = np.max(np.abs(as_[:, ok]))
    vsc = vsc if vsc > 0 else 1.0
    asc = asc if asc > 0 else 1.0
    ev, estv = np.abs(vs - v2)[:, ok], np.abs(v1 - v2)[:, ok]
    ea, esta = np.abs(as_ - a2)[:, ok], np.abs(a1 - a2)[:, ok]
    bad_v = int(np.sum(np.any(ev > 1e-9 * vsc + 2 * estv, axis=0)))
    bad_a = int(np.sum(np.any(ea > 1e-9 * asc + 2 * esta, axis=0)))
    sharp = int(np.sum(np.all(estv < 1e-7 * vsc, axis=0) & np.all(esta < 1e-7 * asc, axis=0)))
    info = dict(v=float(np.max(ev) / vsc), a=float(np.max(ea) / asc))
    return bad_v, bad_a, int(ok.sum()), sharp, info
