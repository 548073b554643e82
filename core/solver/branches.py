"""Branch points: where a group touches its toggle without leaving its assembly range.

At such a point (a change point of a Grashof linkage with s + l = p + q, a parallelogram's
crossing, a rhombus whose outer joints pass through each other, an inverted slider-crank whose pin
runs through the pivot) the two assembly modes meet, and the motion that stays smooth — the one
whose velocity is continuous — continues in the other mode as read from the drawn pose. Keeping
the drawn mode there would turn a parallelogram into an antiparallelogram, or jump by twice a
link length. Passing *close* to a toggle (any gap the arithmetic can resolve) is not a branch
point: the mode is then kept, as it must be.

Branch points are found once per plan on a reference sweep: local minima of the group's assembly
margin (``DyadOut.gap``, mm) are refined by golden-section search, and a minimum within rounding
of zero (relative to the group's size and the coordinates) is a touch. They are stored as offsets
δ ∈ (0, 2π) from the drawn input, in the driver's direction; :func:`flip_factor` turns them into
±1 per sample for any array of inputs (every crossing since the drawn pose flips the mode).
"""
from __future__ import annotations

import math

import numpy as np

from .steps import StepPlan
from .structure import MODAL_KINDS
from .tolerances import BRANCH_REL


REF_SAMPLES = 1440
#: a sampled local minimum of gap/scale below this is refined
CANDIDATE = 2e-2
GOLDEN_STEPS = 80
#: a touch found this close to the drawn input (rad) is the drawn pose itself (the golden search
#: locates a touch, a quadratic minimum, to ~sqrt(rounding / curvature) ≈ 1e-8 rad)
DRAWN_NEAR = 1e-6
TWO_PI = 2.0 * math.pi
#: attribute of a local plan (:meth:`Plan.local`) holding, per link, its state at the reference
#: inputs once the branch offsets of the group that solves it are settled; a later search on
#: the same plan, or on the plan of the same linkage after a drag (:func:`keep_reference_states`),
#: starts from them instead of re-running those groups
REF_STATES = "_branch_reference_states"


def golden_min(f, a: float, b: float, steps: int = GOLDEN_STEPS) -> tuple[float, float]:
    """Golden-section search for the minimum of a unimodal ``f`` on [a, b]: (x, f(x))."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(steps):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = f(d)
    x = 0.5 * (a + b)
    return x, f(x)


def _apart(a: float, b: float) -> bool:
    """Two offsets (rad) that are not the same point of the turn."""
    return abs(math.remainder(a - b, TWO_PI)) > 1e-7


def _leaves_flipped(plan: StepPlan, k: int, idx: list[int], known: dict[str, np.ndarray],
                    others: list[float]) -> bool:
    """The drawn pose of step ``k``'s group is itself a branch point: both assembly modes pass
    through it and it does not say which one the motion takes. Take the branch on which the inner
    joint follows its outer joints (its displacement closest to theirs on average: a
    parallelogram drawn at its crossing stays a parallelogram); True if that is the flipped mode."""
    g = plan.steps[k].group
    near = min((min(d, TWO_PI - d) for d in others), default=math.pi)
    h = min(1e-3, 0.25 * near)
    x = plan.theta0 + plan.direction * np.array([0.0, h])
    at = {j.id: complex(*j.at) for j in plan.linkage.joints}
    moved = {}
    for flip in (False, True):
        states: dict = {}
        branches = dict(known)
        branches[g.name] = np.array([0.0]) if flip else np.empty(0)
        out = plan.run_steps(x, 0, idx, branches, states=states)[g.name]
        m = np.broadcast_to(states[g.known_i].point(at[g.outer_i]), (2,))
        hh = np.broadcast_to(states[g.known_j].point(at[g.outer_j]), (2,))
        ell = np.broadcast_to(out.state_i.point(at[g.inner]), (2,))
        follow = at[g.inner] + 0.5 * ((m[1] - m[0]) + (hh[1] - hh[0]))
        moved[flip] = abs(ell[1] - follow) if np.isfinite(ell[1]) else math.inf
    return moved[True] < moved[False]


def find_branch_points(plan: StepPlan, steps, known: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Add to ``known`` the branch-point offsets (rad, sorted, in [0, 2π]) of the groups of
    ``steps`` (indices in solving order; a step they depend on is solved with the offsets
    ``known`` has for it, none if it has none), keyed by group name.

    One pass in solving order at the reference samples (``REF_SAMPLES`` inputs over one turn):
    each group runs once on the link states of the groups before it, which carry their own
    branch offsets (found just before, or known), so the cost is linear in the number of groups;
    only a group with a candidate touch re-runs its chain at the single inputs of the refinement.

    Decided on :meth:`Plan.local` (the driver pivot at the origin), so that the same linkage
    anywhere in the plane has the same branch points. A branch point at the drawn pose itself is
    stored as 0.0 (the motion leaves it in the other mode: every sample flips) or 2π (it leaves
    in the drawn mode; the point is crossed once per turn)."""
    lp = plan.local()
    todo = {k for k in steps if lp.steps[k].group.name not in known}
    if not todo:
        return known
    sg = lp.direction
    delta = np.arange(REF_SAMPLES) * (TWO_PI / REF_SAMPLES)
    inputs = lp.theta0 + sg * delta
    step_h = TWO_PI / REF_SAMPLES
    run = lp.needed([link for k in todo for link in lp.steps[k].needs]) | todo
    settled = getattr(lp, REF_STATES, None)
    if settled is None:
        settled = {}
        setattr(lp, REF_STATES, settled)
    states: dict = dict(settled)   # link -> state at the reference inputs, filled in solving order
    pending = [k for k in sorted(run)   # (a group settled by an earlier search keeps its states)
               if not (lp.steps[k].group.name in known and lp.steps[k].group.link_i in states
                       and lp.steps[k].group.link_j in states)]
    ring = np.arange(REF_SAMPLES)
    nbr = (np.roll(ring, 1), np.roll(ring, -1))   # each reference sample's neighbours
    i = 0
    while i < len(pending):
        # the rest in one call (one driver state per call); found offsets make the groups after
        # that one run again, on its states in its own mode on each side of them
        outs = lp.run_steps(inputs, 0, pending[i:], known, states=states)
        start, i = i, len(pending)
        for j in range(start, len(pending)):
            k = pending[j]
            g = lp.steps[k].group
            flipped = False
            if k in todo and g.name not in known:
                if g.kind not in MODAL_KINDS or g.fixed:   # fixed: it does not move
                    known[g.name] = np.empty(0)
                else:
                    known[g.name] = _search_group(lp, k, outs[g.name], delta, step_h, known, nbr)
                    if known[g.name].size:
                        lp.run_steps(inputs, 0, [k], known, states=states)
                        flipped = True
            if g.name in known:
                settled[g.link_i], settled[g.link_j] = states[g.link_i], states[g.link_j]
            if flipped:   # the groups after it run again
                i = j + 1
                break
    return known


def keep_reference_states(old: StepPlan, new: StepPlan, links: set[str]) -> None:
    """Start the branch-point search of ``new`` — the linkage of ``old`` after a drag, with the
    same driver pivot, drawn input and groups — from ``old``'s states at the reference inputs of
    ``links`` (links solved by groups the drag did not reach, whose branch offsets ``new`` keeps:
    they see exactly the same inputs)."""
    src = getattr(old.local(), REF_STATES, None)
    if src:
        local = new.local()
        kept = {link: st for link, st in src.items() if link in links}
        drawn = {at for _, at in local.joint_at.values()}
        for st in kept.values():   # the moved joints' old positions are read no more
            st.keep_only(drawn)
        setattr(local, REF_STATES, kept)


#: a margin whose spread over the turn is below this fraction of the group's size is constant
FLAT_REL = 1e-12


def _flat_and_clear(gap: np.ndarray, ok: np.ndarray, size: float, thr: float) -> bool:
    """True when the sampled margin (REF_SAMPLES,) is assembled everywhere, the same at every
    sample up to rounding (a dyad forming a rigid triangle with the link it hangs on) and far
    from zero: no golden-section search there could end within ``thr`` of a branch point."""
    if not ok.all():
        return False
    lo, hi = float(gap.min()), float(gap.max())
    return hi - lo <= FLAT_REL * size and lo > 4.0 * thr + (hi - lo)


def _search_group(lp: StepPlan, k: int, out, delta: np.ndarray, step_h: float,
                  known: dict[str, np.ndarray], nbr: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """The sorted branch offsets of step ``k`` of the local plan ``lp`` from its output ``out``
    at the reference offsets ``delta`` (rad, (REF_SAMPLES,)) in its drawn mode: sampled local
    minima of the assembly margin refined by golden-section search on its chain of steps.
    ``nbr``: the indices of each sample's previous and next sample (round the turn)."""
    step = lp.steps[k]
    name = step.group.name
    sg = lp.direction
    prev, nxt = nbr
    ok = out.ok if out.singular is None else out.ok | out.singular   # assembled
    gap = np.where(ok, out.gap, -np.inf)
    good = ok & ok[prev] & ok[nxt]
    cand = np.flatnonzero(good & (gap <= gap[prev]) & (gap <= gap[nxt]) & (gap < CANDIDATE * step.scale))
    thr = BRANCH_REL * (step.scale + step.coord)
    idx = None

    def margin(d: float) -> float:
        """The signed margin (an overlap within the kernels' tolerance is a minimum below
        zero, not a touch: its |margin| would vanish where it crosses zero)."""
        o = lp.run_steps(np.array([lp.theta0 + sg * d]), 0, idx, known)[name]
        return float(o.gap[0]) if np.isfinite(o.gap[0]) else math.inf

    at_drawn = out.gap[0] if np.isfinite(out.gap[0]) else math.inf   # delta[0] == 0: the drawn pose
    if cand.size == 0 and abs(at_drawn) > 4.0 * thr:   # (the margin below is the same to an ulp)
        return np.empty(0)
    if _flat_and_clear(gap, ok, step.scale + step.coord, thr):
        return np.empty(0)   # its rounding noise is not ~1,000 minima to refine: none is a branch point
    idx = lp.closure(k)
    found: list[float] = []
    for c in cand:
        d, f = golden_min(margin, delta[c] - step_h, delta[c] + step_h)
        d %= TWO_PI
        if abs(f) <= thr and all(_apart(d, e) for e in found):
            found.append(d)
    if abs(margin(0.0)) <= thr:   # drawn at a branch point: it says nothing about the mode after it
        found = [d for d in found if min(d, TWO_PI - d) > DRAWN_NEAR]
        found.append(0.0 if _leaves_flipped(lp, k, idx, known, found) else TWO_PI)
    return np.array(sorted(found))


def flip_factor(offsets: np.ndarray | None, inputs: np.ndarray, theta0: float, direction: float
                ) -> np.ndarray | None:
    """±1 per input: −1 where an odd number of branch points lies between the drawn pose and it."""
    if offsets is None or offsets.size == 0:
        return None
    delta = direction * (inputs - theta0)
    turns = np.floor(delta / TWO_PI)
    frac = delta - turns * TWO_PI
    n = turns * offsets.size + np.searchsorted(offsets, frac, side="right")
    return 1.0 - 2.0 * (n % 2)
