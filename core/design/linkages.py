"""Linkage synthesis in one import: what the CLI and the app call.

::

    from mechsketch.core.design.linkages import (LinkageOptions, path_target, pose_target, function_target,
                                                 synthesize_path, synthesize_motion, synthesize_function)
    result = synthesize_path(path_target(points_mm, closed=True), LinkageOptions(candidates=10),
                             topology="any", progress=callback)
    for c in result.candidates:          # best first
        c.linkage                        # an ordinary Linkage element (id "candidate_1", ...), checked
        c.deviation, c.unit, c.min_transmission_deg, c.kind, c.seconds, c.line()

**Threads.** Every function here is plain Python over numpy and scipy, keeps no state of its
own but the atlases it has loaded (:func:`~.atlas.load_atlas`, shared read-only once made) and
may run on a worker thread. ``progress(fraction, message)`` is called on that thread, often (a
GUI marshals it to its own thread with a queued signal); returning True cancels: the call then
raises :class:`Cancelled` at its next check (within a fraction of a second) and returns nothing.
Run one synthesis at a time per process (two threads building the same atlas would both build
it); the first path synthesis of a topology builds its atlas (minutes, with progress), the
next ones read it from the user cache folder.

**Errors.** Bad requests raise :class:`DesignError` (a ``ValueError`` and a
``MechsketchError``) whose message names what is wrong and what to add, remove or relax; the
targets are checked by ``path_target``/``pose_target``/``function_target`` before any work.

**Results.** A :class:`DesignResult` holds the candidates (:class:`Candidate`), the seconds, the
notes of the search and per-stage timings. A candidate's ``linkage`` validates, drives without a
dead point or branch jump over the target span and exports; joint ``P`` on link ``coupler``
traces the path or carries the poses; function synthesis names its output link ``output``.
Its ``inputs_rad`` are the crank angles (world, rad) at the target's points (to animate it
through them), ``direction`` the crank's sense (the driver's ``speed_rpm`` sign), and
``params``/``sigma``/``topology`` the closed-form design (:mod:`.families`) behind it.
"""
from __future__ import annotations

from .candidates import Candidate
from .function import synthesize_function
from .linkage_path import CHOICES as PATH_TOPOLOGIES
from .linkage_path import synthesize_path
from .motion import synthesize_motion
from .options import DesignResult, LinkageOptions
from .targets import (Cancelled, DesignError, FunctionTarget, PathTarget, PoseTarget, Progress, function_target,
                      path_target, pose_target)

__all__ = ["Cancelled", "Candidate", "DesignError", "DesignResult", "FunctionTarget", "LinkageOptions",
           "PATH_TOPOLOGIES", "PathTarget", "PoseTarget", "Progress", "function_target", "path_target",
           "pose_target", "synthesize_function", "synthesize_motion", "synthesize_path"]
