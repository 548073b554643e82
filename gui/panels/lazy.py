"""Panels that redraw from the controller only when someone can see them."""
from __future__ import annotations


class LazyRefresh:
    """Mixin for a QWidget panel with a ``refresh()``: a change marks it stale; it redraws at once
    when visible, else when next shown (a hidden dock costs nothing while the user drags)."""

    _stale = True

    def _invalidate(self, *_args) -> None:
        """Slot of ``changed(Change)`` and ``selectionChanged()``: redraw now if visible."""
        self._stale = True
        if self.isVisible():
            self.refresh()

    def showEvent(self, event) -> None:  # noqa: N802 - Qt override
        super().showEvent(event)
        if self._stale:
            self.refresh()

    def refresh_if_stale(self) -> None:
        if self._stale:
            self.refresh()
