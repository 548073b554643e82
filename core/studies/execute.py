"""Running a study's tasks: in this process (one thread or a pool of them) or on a Dask cluster,
with progress and cancel, and the same numbers whatever runs them.

A study is cut into tasks of fixed size (a block of designs or builds whose random numbers come
from their own stream, :func:`block_rng`), so a task's result depends only on its index; the
results are gathered in task order and merged in that order. One thread, eight threads, two Dask
workers or two hundred give the same bits.

**The callback API** (the GUI's Study dock runs a study on a worker thread):

- ``progress(done, total)`` is called in the thread that runs the study after each task, with the
  number of tasks finished and the number of tasks, from 0 (before the first) to total;
- ``cancel`` is a ``threading.Event`` (or any object with ``is_set()``, or a callable returning
  True to stop): checked before each task is handed out and after each one finishes; once set,
  no further task starts, tasks queued on a cluster are cancelled, and :class:`StudyCancelled`
  is raised (nothing is written). A task already running on a worker finishes; its result is
  dropped.

``client``: None (this process; ``workers`` threads, default 1), a ``distributed.Client``, or a
scheduler address (``"tcp://host:8786"``) to connect to; an address that cannot be reached
raises :class:`~mechsketch.core.errors.RequestError` naming it.
"""
from __future__ import annotations

import concurrent.futures as cf
from typing import Any, Callable

import numpy as np

from ..errors import MechsketchError, RequestError

#: seconds to wait for a scheduler to answer before reporting it unreachable
CONNECT_TIMEOUT = 10.0


class StudyCancelled(MechsketchError):
    """A study stopped by its ``cancel`` before it finished; nothing was written."""


def block_rng(seed: int, block: int) -> np.random.Generator:
    """The random stream of block ``block`` of a study seeded ``seed`` (independent of how the
    blocks are shared out)."""
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(entropy=int(seed), spawn_key=(int(block),))))


def _stopped(cancel) -> bool:
    if cancel is None:
        return False
    if hasattr(cancel, "is_set"):
        return bool(cancel.is_set())
    return bool(cancel())


def connect(client) -> Any:
    """A ``distributed.Client`` for ``client`` (a client, or a scheduler address)."""
    if not isinstance(client, str):
        return client
    import distributed   # noqa: PLC0415 (heavy; only a distributed run pays for it)

    try:
        return distributed.Client(client, timeout=CONNECT_TIMEOUT, set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise RequestError(f"the Dask scheduler at {client!r} cannot be reached ({exc}); start one "
                           "(dask scheduler) or give --workers N to run here") from None


def run_tasks(fn: Callable[[Any, int], Any], ctx: Any, n: int, client=None, workers: int = 1,
              progress: Callable[[int, int], object] | None = None, cancel=None) -> list:
    """``[fn(ctx, i) for i in range(n)]``, in this process (``workers`` threads) or on the Dask
    cluster of ``client``; see the module docstring for ``progress`` and ``cancel``."""
    if progress is not None:
        progress(0, n)
    if client is not None:
        return _on_cluster(fn, ctx, n, connect(client), progress, cancel)
    out: list = [None] * n
    if workers <= 1:
        for i in range(n):
            if _stopped(cancel):
                raise StudyCancelled(f"cancelled after {i} of {n} tasks")
            out[i] = fn(ctx, i)
            if progress is not None:
                progress(i + 1, n)
        return out
    with cf.ThreadPoolExecutor(max_workers=workers) as pool:
        pending = {}
        nxt = 0
        done = 0
        while nxt < n and len(pending) < 2 * workers:
            pending[pool.submit(fn, ctx, nxt)] = nxt
            nxt += 1
        while pending:
            finished, _ = cf.wait(pending, return_when=cf.FIRST_COMPLETED)
            for f in finished:
                out[pending.pop(f)] = f.result()
                done += 1
                if progress is not None:
                    progress(done, n)
            if _stopped(cancel):
                for f in pending:
                    f.cancel()
                raise StudyCancelled(f"cancelled after {done} of {n} tasks")
            while nxt < n and len(pending) < 2 * workers:
                pending[pool.submit(fn, ctx, nxt)] = nxt
                nxt += 1
    return out


def _on_cluster(fn, ctx, n: int, client, progress, cancel) -> list:
    import distributed   # noqa: PLC0415

    # one object under a key of its own: a tuple scattered as itself went out element by element
    # under content-hashed keys, which the equal numbers of another call shared (and released)
    (remote,) = client.scatter([ctx], broadcast=True, hash=False)
    futures = client.map(fn, [remote] * n, range(n), pure=False)
    index = {f.key: i for i, f in enumerate(futures)}
    out: list = [None] * n
    done = 0
    try:
        for f in distributed.as_completed(futures):
            out[index[f.key]] = f.result()
            done += 1
            if progress is not None:
                progress(done, n)
            if _stopped(cancel):
                raise StudyCancelled(f"cancelled after {done} of {n} tasks")
    except StudyCancelled:
        client.cancel(futures)
        raise
    return out


__all__ = ["CONNECT_TIMEOUT", "StudyCancelled", "block_rng", "connect", "run_tasks"]
