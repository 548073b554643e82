"""What the kinetostatics of a plan needs that no sample changes, found once per plan and cached
(by the plan's identity, with a weak reference proving it): the drawn joints and their links, the
massive links' constants, the constant loads summed per link, the springs and dampers. See
:mod:`.passes`, which uses them.
"""
from __future__ import annotations

import weakref

from ...model.loads import Damper, PointForce, Spring, Torque, default_inertia
from ...solver.kernels import LinkState
from ...solver.plan import Plan

#: mm -> m (and N·mm -> N·m)
MM = 1e-3


def _c(xy) -> complex:
    return complex(float(xy[0]), float(xy[1]))


class _Static:
    """What the kinetostatics of a plan needs that no sample changes, found once per plan: the
    drawn joints and their links; per massive link (link, d, mk, alpha_coef): the centre's drawn
    offset d from the link's anchor (mm), mk = −m·1e-3 (kg, with mm→m) and the coefficient of α
    in its inertia moment (mk·|d|² − I, I in kg·m·mm); the constant loads summed per link (force N,
    W = Σ conj(p0 − a0)·f N·mm, torques N·mm) and on the frame; the springs and dampers."""

    def __init__(self, plan: Plan, anchors: dict[str, complex]) -> None:
        lk = plan.linkage
        self.anchors = anchors
        self.at = at = {j.id: _c(j.at) for j in lk.joints}
        self.carriers = {j.id: lk.links_of(j.id) for j in lk.joints}
        self.link_ids = lk.link_ids
        ground = lk.ground
        pivot = at[lk.driver.pivot]
        g = _c(lk.gravity) if lk.gravity is not None else 0j
        self.F0: dict[str, object] = {k: 0j for k in lk.link_ids}
        self.M0: dict[str, object] = {k: 0.0 for k in lk.link_ids}
        self.wconst: dict[str, complex] = {}
        self.masses: list[tuple] = []
        for m in lk.masses:
            k = m.link
            if k == ground or (m.mass == 0.0 and not m.inertia):
                continue
            pts = [at[j] for j in lk.link(k).joints]
            c0 = _c(m.com) if m.com is not None else sum(pts) / len(pts)
            span = max((abs(p - q) for p in pts for q in pts), default=0.0)
            inertia = (m.inertia if m.inertia is not None else default_inertia(m.mass, span)) / MM  # kg·m·mm
            d = c0 - anchors[k]
            mk = -m.mass * MM
            self.masses.append((k, d, mk, mk * abs(d) ** 2 - inertia))
            if g and m.mass:
                self.F0[k] = self.F0[k] + m.mass * g
                self.wconst[k] = self.wconst.get(k, 0j) + d.conjugate() * (m.mass * g)
        self.springs: list[tuple] = []
        for ld in lk.loads:
            if isinstance(ld, PointForce):
                f, k, p0 = _c(ld.force), ld.link, _c(ld.at)
                self.F0[k] = self.F0[k] + f
                if k == ground:
                    self.M0[k] = self.M0[k] + ((p0 - pivot).conjugate() * f).imag
                else:
                    self.wconst[k] = self.wconst.get(k, 0j) + (p0 - anchors[k]).conjugate() * f
            elif isinstance(ld, Torque):
                self.M0[ld.link] = self.M0[ld.link] + ld.torque / MM
            elif isinstance(ld, (Spring, Damper)):
                (a, pa0), (b, pb0) = ((x.link, _c(x.at)) for x in ld.ends)
                coef = (ld.stiffness, ld.stiffness * ld.rest_length) if isinstance(ld, Spring) else (ld.damping,)
                self.springs.append((a, pa0, b, pb0, coef))
        self.wconst = {k: w for k, w in self.wconst.items() if w != 0}


#: the static data of recent plans, by id (with a weak reference that proves the id still names
#: the same plan)
_STATIC: dict[int, tuple] = {}
_STATIC_MAX = 32


def _static(plan: Plan, st: dict[str, LinkState]) -> _Static:
    anchors = {k: s.a0 for k, s in st.items()}
    hit = _STATIC.get(id(plan))
    if hit is not None and hit[0]() is plan and hit[1].anchors == anchors:
        return hit[1]
    data = _Static(plan, anchors)
    if len(_STATIC) >= _STATIC_MAX:
        _STATIC.pop(next(iter(_STATIC)))
    _STATIC[id(plan)] = (weakref.ref(plan), data)
    return data
