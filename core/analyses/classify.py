"""What kind of linkage it is, in the designer's words: Grashof and the four-bar's type, the
slider-crank's kind, an actuator's stroke, and the stroke and time ratio of each output.

- **Four-bar** (the crank's first group is an RRR hung on the crank and the frame): shortest s,
  longest l and the other two p, q of ground, crank, coupler and rocker. Grashof when
  s + l < p + q; its type follows the shortest link: the crank (crank-rocker), the ground (double
  crank), the coupler (double rocker), the rocker (rocker-crank: the input cannot turn fully).
  s + l = p + q is a change-point linkage; s + l > p + q a non-Grashof triple rocker.
- **Slider-crank** (an RRP on the crank with its guide on the frame): centric or offset by e
  (the crank pivot's distance from the pin's line); the crank turns fully when r + |e| ≤ l.
  **Inverted slider-crank** (an RPR on the crank and the frame): the guide rocks when the crank
  is shorter than the pivots' distance, else it turns (a Whitworth drive).
- **Outputs**: every link pivoted on the frame (a rocker) or sliding on a frame guide (a slider)
  that the driver moves: its travel over the cycle (angle, °, or stroke, mm) and, when it swings
  back and forth over a cycle that assembles everywhere, the time ratio: the time from its
  least to its greatest value over the time back (> 1: a quick return). Extremes are refined by
  golden-section search in time on the cycle's own law, so the ratio is exact for any law.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.drivers import DriverKind
from ..model.linkage import JointKind, Linkage
from ..solver.motion_law import at_times
from ..solver.plan import Plan, Solution
from ..solver.structure import Group, GroupKind

#: two lengths that differ by less than this relative amount are equal (Grashof equality)
EQUAL_REL = 1e-9
GOLDEN = 60


def _c(xy) -> complex:
    return complex(float(xy[0]), float(xy[1]))


def _d(lk: Linkage, a: str, b: str) -> float:
    return abs(_c(lk.joint(a).at) - _c(lk.joint(b).at))


def fourbar_type(ground: float, crank: float, coupler: float, rocker: float) -> tuple[str, str]:
    """(Grashof class, type) of a four-bar driven by its crank, from its four lengths (mm)."""
    named = {"ground": ground, "crank": crank, "coupler": coupler, "rocker": rocker}
    vals = sorted(named.values())
    s, p, q, l = vals
    lhs, rhs = s + l, p + q
    shortest = min(named, key=named.get)
    tol = EQUAL_REL * rhs
    if abs(lhs - rhs) <= tol:
        cls = f"change point (s + l = p + q = {rhs:.6g} mm)"
        kind = {"crank": "crank-rocker", "ground": "double crank", "coupler": "double rocker",
                "rocker": "rocker-crank"}[shortest] + " with change points (the links fold into one line)"
    elif lhs < rhs:
        cls = f"Grashof (s + l = {lhs:.6g} < p + q = {rhs:.6g} mm)"
        kind = {"crank": "crank-rocker (the crank turns fully, the rocker swings)",
                "ground": "double crank (drag link: both side links turn fully)",
                "coupler": "double rocker (Grashof: the coupler turns fully, crank and rocker swing)",
                "rocker": "rocker-crank (the rocker could turn fully; the crank only swings)"}[shortest]
    else:
        cls = f"non-Grashof (s + l = {lhs:.6g} > p + q = {rhs:.6g} mm)"
        kind = "triple rocker (double rocker: no link turns fully)"
    return cls, kind


def _first_group(plan: Plan) -> Group | None:
    drv = plan.linkage.driver
    for step in plan.steps:
        g = step.group
        if {g.known_i, g.known_j} == {drv.link, plan.linkage.ground} and not g.fixed:
            return g
    return None


def _structure_lines(lk: Linkage, plan: Plan) -> list[str]:
    drv = lk.driver
    if drv.kind is not DriverKind.CRANK:
        kind = "cylinder between two pivots" if drv.kind is DriverKind.CYLINDER else "slider on a fixed guide"
        lo, hi = drv.stroke
        return [f"input: {kind} ({drv.link!r} on {drv.pivot!r}), stroke {lo:g} to {hi:g} mm "
                f"({hi - lo:g} mm), law {drv.law.kind.value}"]
    out = [f"input: crank {drv.link!r} about {drv.pivot!r}, law {drv.law.kind.value}"]
    g = _first_group(plan)
    if g is None:
        return out
    on_crank_i = g.known_i == drv.link
    oc, og = (g.outer_i, g.outer_j) if on_crank_i else (g.outer_j, g.outer_i)
    if g.kind is GroupKind.RRR:
        link_c, link_g = (g.link_i, g.link_j) if on_crank_i else (g.link_j, g.link_i)
        a, b = _d(lk, drv.pivot, oc), _d(lk, oc, g.inner)
        c, d = _d(lk, og, g.inner), _d(lk, drv.pivot, og)
        cls, kind = fourbar_type(d, a, b, c)
        out.append(f"four-bar {drv.pivot}–{oc}–{g.inner}–{og}: ground {d:.6g}, crank {a:.6g}, coupler "
                   f"{link_c!r} {b:.6g}, rocker {link_g!r} {c:.6g} mm; {cls}; {kind}")
    elif g.kind is GroupKind.RRP and g.known_j == lk.ground:
        r, rod = _d(lk, drv.pivot, g.outer_i), _d(lk, g.outer_i, g.inner)
        guide = lk.joint(g.outer_j)
        u = complex(math.cos(math.radians(guide.axis_deg or 0.0)), math.sin(math.radians(guide.axis_deg or 0.0)))
        v = _c(lk.joint(drv.pivot).at) - _c(lk.joint(g.inner).at)
        e = (u.conjugate() * v).imag
        size = max(r, rod, 1.0)
        kind = "centric" if abs(e) <= EQUAL_REL * size else f"offset (e = {abs(e):.6g} mm)"
        turns = (f"the crank turns fully (r + |e| = {r + abs(e):.6g} ≤ l = {rod:.6g} mm)" if r + abs(e) <= rod
                 else f"the crank cannot turn fully (r + |e| = {r + abs(e):.6g} > l = {rod:.6g} mm)")
        out.append(f"slider-crank: {kind}, crank r {r:.6g} mm, rod l {rod:.6g} mm; {turns}")
    elif g.kind is GroupKind.RPR:
        pin = g.outer_i if on_crank_i else g.outer_j
        r, dist = _d(lk, drv.pivot, pin), _d(lk, drv.pivot, og)
        how = ("the guide swings (crank shorter than the pivots' distance)" if r < dist else
               "the guide turns fully (a Whitworth quick-return drive)")
        out.append(f"inverted slider-crank: crank {r:.6g} mm, pivots {dist:.6g} mm apart; {how}")
    return out


def _outputs(lk: Linkage, plan: Plan) -> list[tuple[str, str, str | None]]:
    """(link, "rocker" | "slider", guide joint or pivot) for each output of the linkage."""
    out = []
    ground = set(lk.link(lk.ground).joints)
    drv = lk.driver
    extra = set(getattr(plan.drive, "extra", {}) or ())
    for step in plan.steps:
        g = step.group
        if g.fixed:
            continue
        for link in (g.link_i, g.link_j):
            if link == drv.link or link in extra:
                continue
            joints = lk.link(link).joints
            pivots = [j for j in joints if j in ground and lk.joint(j).kind is JointKind.R]
            guides = [j for j in joints if j in ground and lk.joint(j).kind is JointKind.P]
            if pivots:
                out.append((link, "rocker", pivots[0]))
            elif guides:
                out.append((link, "slider", guides[0]))
    return out


def _value(sol: Solution, lk: Linkage, link: str, kind: str, joint: str) -> np.ndarray:
    """The output's coordinate: a rocker's angle (rad, unwrapped), a slider's position along its
    guide (mm)."""
    if kind == "rocker":
        return sol.angle(link)
    j = lk.joint(joint)
    u = np.array([math.cos(math.radians(j.axis_deg or 0.0)), math.sin(math.radians(j.axis_deg or 0.0))])
    return sol.point(link, j.at) @ u


@dataclass(frozen=True)
class OutputMotion:
    """How an output moves over one cycle: a ``rocker``'s angle (rad) or a ``slider``'s position
    along its guide (mm) from ``low`` to ``high``; ``t_out`` the time (s) from low to high and
    ``t_back`` from high back to low (None when it turns fully or stops at an assembly limit);
    ``note``: why there is no stroke."""

    link: str
    kind: str
    joint: str
    low: float = math.nan
    high: float = math.nan
    t_out: float | None = None
    t_back: float | None = None
    note: str = ""

    @property
    def travel(self) -> float:
        """high − low: the swing (rad) or the stroke (mm)."""
        return self.high - self.low

    @property
    def time_ratio(self) -> float:
        """t_out / t_back (NaN when there is none)."""
        return self.t_out / self.t_back if self.t_out is not None and self.t_back else math.nan

    def text(self) -> str:
        if self.note:
            return f"output {self.link!r} ({self.kind}): {self.note}"
        if self.kind == "rocker":
            travel = (f"swings {math.degrees(self.travel):.4f}° (angle {math.degrees(self.low):.4f}° to "
                      f"{math.degrees(self.high):.4f}°)")
        else:
            travel = f"stroke {self.travel:.6g} mm (along its guide, {self.low:.6g} to {self.high:.6g} mm)"
        return (f"output {self.link!r} ({self.kind}): {travel}; time ratio {self.time_ratio:.4f} "
                f"(out {self.t_out:.6g} s, back {self.t_back:.6g} s)")


#: golden-section steps taken per solve: the points of the next LOOKAHEAD steps for every outcome
#: of their comparisons (2^LOOKAHEAD − 1 per search) are solved at once
LOOKAHEAD = 4


def _advance(a, b, c, d, left, g: float):
    """One golden-section step from bracket [a, b] with inner points c < d, the smaller value at
    c where ``left``: the new bracket, inner points and the new point x (whose value is needed)."""
    a = np.where(left, a, c)
    b = np.where(left, d, b)
    x = np.where(left, b - g * (b - a), a + g * (b - a))
    return a, b, np.where(left, x, d), np.where(left, c, x), x


def _golden_min_all(f, a: np.ndarray, b: np.ndarray, steps: int = GOLDEN,
                    lookahead: int = LOOKAHEAD) -> tuple[np.ndarray, np.ndarray]:
    """Golden-section searches for the minima of m unimodal functions at once, on brackets
    [a, b] (shape (m,)): (x, f(x)), (m,), with the same iterates, bit for bit, as
    :func:`~mechsketch.core.solver.branches.golden_min` on each search alone.

    ``f`` maps points (k·m,) to the values there, point j belonging to search j mod m. Where a
    step's new point lies depends only on the comparisons before it, so the points of the next
    ``lookahead`` steps for every outcome of those comparisons are solved in one call of ``f``
    and the taken branch is kept: about steps / lookahead calls."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = np.array(a, dtype=float), np.array(b, dtype=float)
    m = a.shape[0]
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = np.split(f(np.concatenate((c, d))), 2)
    ar = np.arange(m)
    done = 0
    while done < steps:
        depth = min(lookahead, steps - done)
        left0 = fc < fd                  # NaN compares False: the right branch, as golden_min
        # level l: 2^l nodes, (2^l, m); node 2i is node i's child with a left step, 2i + 1 right
        levels = [tuple(z[None] for z in _advance(a, b, c, d, left0, g))]
        for lev in range(1, depth):
            pa, pb, pc, pd, _ = (np.repeat(z, 2, axis=0) for z in levels[-1])
            h = np.tile(np.array([True, False]), 2 ** (lev - 1))[:, None]
            levels.append(_advance(pa, pb, pc, pd, h, g))
        fx_all = f(np.concatenate([lv[4].ravel() for lv in levels]))
        node = np.zeros(m, dtype=np.intp)
        pos = 0
        for lev, (la, lb, lc, ld, _) in enumerate(levels):
            if lev:
                left = fc < fd
                node = 2 * node + np.where(left, 0, 1)
            else:
                left = left0
            fx = fx_all[pos:pos + la.size].reshape(la.shape)[node, ar]
            pos += la.size
            a, b, c, d = la[node, ar], lb[node, ar], lc[node, ar], ld[node, ar]
            fc, fd = np.where(left, fx, fd), np.where(left, fc, fx)
        done += depth
    x = 0.5 * (a + b)
    return x, f(x)


def _needed_joints(plan: Plan, links: list[str]) -> list[str] | None:
    """Joints whose solve gives every one of ``links`` and only what they depend on: the inner
    joint of the group that solves each (None, i.e. every group, when one is not found so)."""
    joints = []
    for link in links:
        k = plan.solved_by.get(link, -1)
        if k < 0:
            return None
        g = plan.steps[k].group
        if plan.solved_by.get(plan.reporter.get(g.inner, ""), -1) != k:
            return None
        joints.append(g.inner)
    return joints


def _values_at(sol: Solution, lk: Linkage, plan: Plan, outs: list[tuple[str, str, str]]) -> np.ndarray:
    """Output ``i``'s coordinate (as :func:`_value`, but per sample: a rocker's angle is not
    unwrapped along the samples) at samples j of ``sol`` with j mod 2m = 2i or 2i + 1 (k·2m
    samples for m outputs): shape (k·2m,), rad or mm, NaN where not assembled."""
    m2 = 2 * len(outs)
    k = len(sol) // m2
    c_all, s_all, y = np.ones((k, m2)), np.zeros((k, m2)), np.zeros((k, m2))
    rocker = np.zeros(m2, dtype=bool)
    angle0 = np.zeros(m2)
    for i, (link, kind, joint) in enumerate(outs):
        sl = slice(2 * i, 2 * i + 2)
        if kind == "rocker":
            c, s = sol.link_state(link).cs
            c_all[:, sl] = np.reshape(c, (k, m2))[:, sl] if np.ndim(c) else c
            s_all[:, sl] = np.reshape(s, (k, m2))[:, sl] if np.ndim(s) else s
            rocker[sl] = True
            angle0[sl] = plan.angle0.get(link, 0.0)
        else:
            j = lk.joint(joint)
            a = math.radians(j.axis_deg or 0.0)
            y[:, sl] = sol.point(link, j.at).reshape(k, m2, 2)[:, sl] @ np.array([math.cos(a), math.sin(a)])
    y = np.where(rocker, np.arctan2(s_all, c_all), y)
    y[~np.asarray(sol.valid, dtype=bool).reshape(k, m2)] = np.nan
    return (y + angle0).ravel()


def output_motions(lk: Linkage, plan: Plan, sol: Solution, full: bool | None = None) -> list[OutputMotion]:
    """The motion of every output over the cycle swept by ``sol`` (see the module docstring).
    ``full``: whether the whole cycle assembles, as the diagnostics found it between the samples
    (:func:`~mechsketch.core.solver.diagnostics.diagnose`); None: as the samples say. Where it does
    not, no output has a stroke over the cycle.

    The extremes of all outputs are refined together: one golden-section search per extreme (2m
    for m outputs), all advanced :data:`LOOKAHEAD` steps per solve of only the groups the outputs
    depend on (2m·(2^LOOKAHEAD − 1) inputs: :func:`_golden_min_all`), with the same iterates as
    one search and one input at a time."""
    drv = lk.driver
    T = drv.period
    n = len(sol)
    dt = T / n
    motions: list[OutputMotion | None] = []
    todo: list[tuple[int, str, str, str]] = []
    lo: list[float] = []
    hi: list[float] = []
    for link, kind, joint in _outputs(lk, plan):
        y = _value(sol, lk, link, kind, joint)
        if full is False or not np.all(np.isfinite(y)):
            motions.append(OutputMotion(link, kind, joint, note="the cycle stops at assembly limits (no stroke "
                                                                "over a full cycle)"))
            continue
        if kind == "rocker" and abs(y[-1] + (y[1] - y[0]) - y[0]) > math.pi:   # unwrapped: it gained a turn
            motions.append(OutputMotion(link, kind, joint, note=f"turns fully about {joint}"))
            continue
        k_lo, k_hi = int(np.argmin(y)), int(np.argmax(y))
        todo.append((len(motions), link, kind, joint))
        motions.append(None)
        lo += [sol.t[k_lo] - dt, sol.t[k_hi] - dt]     # search 2i: output i's least value; 2i + 1: its greatest
        hi += [sol.t[k_lo] + dt, sol.t[k_hi] + dt]
    if todo:
        outs = [(link, kind, joint) for _, link, kind, joint in todo]
        joints = _needed_joints(plan, [link for link, _, _ in outs])
        sign = np.tile([1.0, -1.0], len(outs))   # the greatest value is the least of its negative

        def f(t: np.ndarray) -> np.ndarray:
            if drv.linear or not drv.law.is_constant:
                q = at_times(drv, plan.theta0, t).q
            else:
                q = plan.theta0 + math.copysign(2 * math.pi / T, drv.speed_rpm) * t   # t < 0: before the drawn pose
            return np.tile(sign, len(t) // len(sign)) * _values_at(plan.evaluate(q, order=0, joints=joints),
                                                                   lk, plan, outs)

        t_ext, f_ext = _golden_min_all(f, np.array(lo), np.array(hi))
        for i, (pos, link, kind, joint) in enumerate(todo):
            t_lo, y_lo, t_hi, neg = t_ext[2 * i], f_ext[2 * i], t_ext[2 * i + 1], f_ext[2 * i + 1]
            fwd = (t_hi - t_lo) % T
            motions[pos] = OutputMotion(link, kind, joint, float(y_lo), float(-neg), float(fwd), float(T - fwd))
    return [m for m in motions if m is not None]




def classification(lk: Linkage, plan: Plan, sol: Solution | None, full: bool | None = None) -> list[str]:
    """Lines describing the linkage's kind and its outputs (see the module docstring); ``sol`` is
    the cycle's sweep (outputs are not described without it); ``full`` as for :func:`output_motions`."""
    out = _structure_lines(lk, plan)
    if sol is not None and len(sol) > 2:
        out += [m.text() for m in output_motions(lk, plan, sol, full)]
    return out


__all__ = ["OutputMotion", "classification", "fourbar_type", "output_motions"]
