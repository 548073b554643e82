"""Instant centres and centrodes of any link of a solved linkage.

For a moving link K with a point X (velocity v_X) and angular velocity ω, the instant centre
relative to the frame is P = X + J v_X / ω (J the 90° rotation): the point of K with zero
velocity. Relative to another link L, velocities relative to L are used: v_rel = v_X − v_L(X)
with v_L(X) = v_Y + ω_L J (X − Y) for a point Y of L, and ω_rel = ω_K − ω_L. Where |ω_rel| is
below ``rel_tol`` times the largest angular speed of the motion, the relative motion is a pure
translation (centre at infinity), or at rest for an instant (centre undefined): the sample is
flagged, not an error.

The fixed centrode is the locus of P in the frame (or, with ``relative_to``, in L's own frame,
drawn-pose coordinates); the moving centrode is the locus of P in K's own frame (drawn-pose
coordinates). Only the solution's public contract is used: ``point``, ``point_velocity``,
``omega``, ``input``, ``valid``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import GeometryError
from .table import Table


def _j(v: np.ndarray) -> np.ndarray:
    return np.stack([-v[:, 1], v[:, 0]], axis=-1)


def _unrotate(v: np.ndarray, rho: np.ndarray) -> np.ndarray:
    c, s = np.cos(rho), np.sin(rho)
    return np.stack([c * v[:, 0] + s * v[:, 1], -s * v[:, 0] + c * v[:, 1]], axis=-1)


@dataclass
class Centrodes:
    """Instant centres of ``link`` relative to ``relative_to`` (None: the frame) per sample.

    ``input`` (N,) rad: driver angle; ``P`` (N, 2) mm: fixed-centrode point (in the frame, or in
    the reference link's frame); ``p`` (N, 2) mm: moving-centrode point in the link's frame;
    ``valid`` (N,) bool: False where the solution is invalid or the relative motion is a pure
    translation or at rest (``translation`` True; then P and p are NaN); ``omega_rel`` (N,) rad/s.

    For drawing each centrode on its own body: ``world`` (N, 2) mm the instant centre in the frame
    at each sample; the link's frame maps a drawn point x to ``at + Rot(rotation)(x − origin)``
    (``at`` (N, 2) mm, ``rotation`` (N,) rad, ``origin`` the link's first joint as drawn), and the
    reference link's likewise (``ref_*``; None relative to the frame).
    """

    link: str
    relative_to: str | None
    input: np.ndarray
    P: np.ndarray
    p: np.ndarray
    valid: np.ndarray
    omega_rel: np.ndarray
    translation: np.ndarray
    world: np.ndarray | None = None
    origin: tuple[float, float] = (0.0, 0.0)
    at: np.ndarray | None = None
    rotation: np.ndarray | None = None
    ref_origin: tuple[float, float] | None = None
    ref_at: np.ndarray | None = None
    ref_rotation: np.ndarray | None = None

    def drawable(self, limit: float) -> np.ndarray:
        """(N,) bool: valid samples whose centres (fixed and moving) lie within ``limit`` mm of
        the link's reference points - near a translation the centres run off to infinity."""
        with np.errstate(invalid="ignore"):
            near_p = np.linalg.norm(self.p - np.asarray(self.origin), axis=1) <= limit
            ref = np.asarray(self.ref_origin) if self.ref_origin is not None else np.asarray(self.origin)
            near_P = np.linalg.norm(self.P - ref, axis=1) <= limit
        return self.valid & near_p & near_P

    def point(self, size: float, rel: float = 1e-9) -> tuple[float, float] | None:
        """The point (mm, in the reference body's frame) the centrode shrinks to when the link
        turns about a fixed pivot of the reference body (they share a pivot: both centrodes are
        that one point), else None. ``size`` mm: the linkage's size; the centres must all lie
        within ``rel`` of it of their mean (the solver's rounding)."""
        ok = self.valid
        if not ok.any():
            return None
        P, p = self.P[ok], self.p[ok]
        spread = max(float(np.max(np.linalg.norm(P - P.mean(axis=0), axis=1))),
                     float(np.max(np.linalg.norm(p - p.mean(axis=0), axis=1))))
        if spread > rel * max(size, 1.0):
            return None
        x, y = P.mean(axis=0)
        return float(x), float(y)

    def point_message(self, at: tuple[float, float]) -> str:
        """What to tell the user of a point-like centrode at ``at`` (mm)."""
        rel = "the frame" if self.relative_to is None else f"link {self.relative_to!r}"
        return (f"the centrode is a point at ({at[0]:.9g}, {at[1]:.9g}) mm: link {self.link!r} turns about a pivot "
                f"it shares with {rel}, so both centrodes are that pivot (no curve to cut; choose a link that does "
                f"not share a pivot with {rel}, or another --relative-to)")

    def table(self) -> Table:
        """CSV table with columns ``input P.x P.y p.x p.y valid`` (rad, mm, 1/0)."""
        return Table.from_columns({"input": self.input, "P.x": self.P[:, 0], "P.y": self.P[:, 1],
                                   "p.x": self.p[:, 0], "p.y": self.p[:, 1], "valid": self.valid.astype(float)},
                                  integer={"valid"})


def _frame(sol, link: str, x0: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Position (N, 2) of the link's point drawn at x0, and the link's rotation from the drawn pose (N,)."""
    X = np.asarray(sol.point(link, x0), dtype=float)
    X1 = np.asarray(sol.point(link, (x0[0] + 1.0, x0[1])), dtype=float)
    d = X1 - X
    return X, np.arctan2(d[:, 1], d[:, 0])


def linkage_centrodes(solution, linkage, link: str, relative_to: str | None = None,
                      rel_tol: float = 1e-9) -> Centrodes:
    """Instant centres and both centrodes of ``link`` of a solved ``linkage`` (see module docstring).

    ``solution`` needs velocities (a solve of order ≥ 1). Raises :class:`GeometryError` naming the
    id for an unknown link, the ground link, or ``relative_to`` equal to ``link``.
    """
    ids = linkage.link_ids
    for what, lid in (("link", link), ("relative_to", relative_to)):
        if lid is not None and lid not in ids:
            raise GeometryError(f"linkage {linkage.id!r} has no link {lid!r} (links: {', '.join(ids)})")
    if link == linkage.ground:
        raise GeometryError(f"link {link!r} is the ground: it has no motion, hence no centrodes")
    if relative_to == link:
        raise GeometryError(f"the centrodes of link {link!r} relative to itself are undefined")
    ref_link = None if relative_to in (None, linkage.ground) else relative_to

    x0 = linkage.joint(linkage.link(link).joints[0]).at
    X, rho_k = _frame(solution, link, x0)
    v = np.asarray(solution.point_velocity(link, x0), dtype=float)
    w_k = np.asarray(solution.omega(link), dtype=float)
    w_ref = np.abs(w_k)
    if ref_link is not None:
        y0 = linkage.joint(linkage.link(ref_link).joints[0]).at
        Y, rho_l = _frame(solution, ref_link, y0)
        vy = np.asarray(solution.point_velocity(ref_link, y0), dtype=float)
        w_l = np.asarray(solution.omega(ref_link), dtype=float)
        v = v - (vy + w_l[:, None] * _j(X - Y))
        w = w_k - w_l
        w_ref = np.maximum(w_ref, np.abs(w_l))
    else:
        w = w_k
    drv = np.abs(np.asarray(solution.omega(linkage.driver.link), dtype=float))
    scale = max(float(np.nanmax(np.concatenate([w_ref, drv]))) if np.any(np.isfinite(w_ref)) else 0.0, 1e-300)
    ok = np.asarray(solution.valid, dtype=bool) & np.isfinite(w) & np.all(np.isfinite(v), axis=1)
    translation = ok & (np.abs(w) <= rel_tol * scale)
    valid = ok & ~translation
    with np.errstate(divide="ignore", invalid="ignore"):
        Pg = X + _j(v) / np.where(valid, w, np.nan)[:, None]
    p = _unrotate(Pg - X, rho_k) + np.asarray(x0)
    P = Pg if ref_link is None else _unrotate(Pg - Y, rho_l) + np.asarray(y0)
    out = Centrodes(link, relative_to, np.asarray(solution.input, dtype=float), P, p, valid, w, translation,
                    world=Pg, origin=(float(x0[0]), float(x0[1])), at=X, rotation=rho_k)
    if ref_link is not None:
        out.ref_origin, out.ref_at, out.ref_rotation = (float(y0[0]), float(y0[1])), Y, rho_l
    return out


def runs(mask: np.ndarray, cyclic: bool = True) -> list[np.ndarray]:
    """The maximal runs of True in ``mask`` (N,), as index arrays in order; with ``cyclic`` a run
    through the end continues at the start (one revolution is a closed loop). An all-True mask
    gives one run of all N indices."""
    mask = np.asarray(mask, dtype=bool)
    n = len(mask)
    if n == 0 or not mask.any():
        return []
    if mask.all():
        return [np.arange(n)]
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    out = [np.arange(a, b) for a, b in zip(edges[::2], edges[1::2])]
    if cyclic and len(out) > 1 and mask[0] and mask[-1]:
        out = [np.concatenate([out[-1], out[0]])] + out[1:-1]
    return out
