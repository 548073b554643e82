"""A seeded monkey (issues 13 and 20): random user events on the whole app — menu actions and
every example in turn, every canvas tool with clicks and drags near joints and anywhere, handle
drags of Geneva drives and rolling levers, keys (tool shortcuts, digits, Ctrl+Z / Ctrl+Y, Esc,
Space), the wheel over the canvas and over the properties' boxes, numbers typed into the
properties panel (extremes and garbage too: 1e5 points is over a minute of synthesis, solved
off the GUI thread), the selector, combo boxes, the scrub bar, play/pause and the animation's
ticks, undo/redo — in bursts without the event loop running between them (a user faster than the
app) — and no exception may escape into Qt's event loop.

Used by tests/gui/test_monkey.py (a bounded run) and tools/gui_monkey.py (the big run:
``python tools/gui_monkey.py --events 10000``). The seed is fixed, so a failure replays; the
log keeps the events before it.
"""
from __future__ import annotations

import os
import random
import sys
import traceback

from PySide6.QtCore import QEvent, QPoint, QPointF, Qt
from PySide6.QtGui import QWheelEvent
from PySide6.QtWidgets import QApplication, QWidget

#: fixed for CI; MECHSKETCH_MONKEY_SEED explores further by hand
SEED = int(os.environ.get("MECHSKETCH_MONKEY_SEED", "20261124"))
TEXTS = ["0", "1", "-1", "12.5", "250", "1e9", "1e10", "1e308", "-1e308", "5e-324", "nan", "inf", "-0",
         "abc", "", "3,5", "1e5", "100001", "0.0001", "360", "-720"]
KEYS = [Qt.Key.Key_Escape, Qt.Key.Key_Delete, Qt.Key.Key_Backspace, Qt.Key.Key_Return, Qt.Key.Key_Space,
        Qt.Key.Key_F, Qt.Key.Key_1, Qt.Key.Key_Period, Qt.Key.Key_Comma, Qt.Key.Key_Z, Qt.Key.Key_Tab,
        Qt.Key.Key_3, Qt.Key.Key_4, Qt.Key.Key_8, Qt.Key.Key_9, Qt.Key.Key_W, Qt.Key.Key_Y, Qt.Key.Key_X,
        Qt.Key.Key_P, Qt.Key.Key_R, Qt.Key.Key_S, Qt.Key.Key_G, Qt.Key.Key_C, Qt.Key.Key_T, Qt.Key.Key_L]
CTRL_KEYS = [Qt.Key.Key_Z, Qt.Key.Key_Y, Qt.Key.Key_N]
SKIP_ACTIONS = {"quit"}
FRESH = 250   # every FRESH-th event opens an example


class Monkey:
    """Random user events on one app; ``log`` keeps what was done."""

    def __init__(self, parts, qtbot, rng: random.Random) -> None:
        self.parts, self.qtbot, self.rng = parts, qtbot, rng
        self.window = parts.window
        self.view = parts.window.canvas
        self.vp = self.view.viewport()
        self.log: list[str] = []
        self.actions = sorted(k for k in self.window.actions if k not in SKIP_ACTIONS)
        self.tools = sorted(self.view.toolbox.actions)

    # -- where ---------------------------------------------------------------------------------
    def world_point(self) -> tuple[float, float]:
        """Near a joint of the scene (often) or anywhere in the visible window."""
        rng = self.rng
        joints = [j.at for e in self.parts.controller.scene.elements for j in getattr(e, "joints", ())]
        if joints and rng.random() < 0.6:
            x, y = rng.choice(joints)
            return x + rng.gauss(0, 3), y + rng.gauss(0, 3)
        r = self.view.mapToScene(self.vp.rect()).boundingRect()
        return rng.uniform(r.left(), r.right()), rng.uniform(r.top(), r.bottom())

    def screen(self, xy) -> QPoint:
        p = self.view.mapFromScene(QPointF(*xy))
        return QPoint(max(0, min(self.vp.width() - 1, p.x())), max(0, min(self.vp.height() - 1, p.y())))

    # -- what ----------------------------------------------------------------------------------
    def action(self) -> None:
        name = self.rng.choice(self.actions)
        self.log.append(f"action {name}")
        act = self.window.actions[name]
        if act.isEnabled():
            act.trigger()

    def tool(self) -> None:
        name = self.rng.choice(self.tools)
        self.log.append(f"tool {name}")
        self.view.toolbox.actions[name].trigger()

    def click(self) -> None:
        p = self.screen(self.world_point())
        mods = self.rng.choice([Qt.KeyboardModifier.NoModifier] * 4 + [Qt.KeyboardModifier.ShiftModifier,
                                                                          Qt.KeyboardModifier.ControlModifier])
        self.log.append(f"click {p.x()},{p.y()} {mods}")
        self.qtbot.mouseMove(self.vp, p)
        if self.rng.random() < 0.1:
            self.qtbot.mouseDClick(self.vp, Qt.MouseButton.LeftButton, mods, p)
        else:
            self.qtbot.mouseClick(self.vp, Qt.MouseButton.LeftButton, mods, p)

    def drag(self) -> None:
        a, b = self.screen(self.world_point()), self.screen(self.world_point())
        self.log.append(f"drag {a.x()},{a.y()} -> {b.x()},{b.y()}")
        self.qtbot.mouseMove(self.vp, a)
        self.qtbot.mousePress(self.vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, a)
        steps = self.rng.randint(1, 5)
        for k in range(1, steps + 1):
            t = k / steps
            self.qtbot.mouseMove(self.vp, QPoint(round(a.x() + t * (b.x() - a.x())), round(a.y() + t * (b.y() - a.y()))))
        if self.rng.random() < 0.9:
            self.qtbot.mouseRelease(self.vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, b)
        else:
            self.qtbot.keyClick(self.vp, Qt.Key.Key_Escape)
            self.qtbot.mouseRelease(self.vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, b)

    def key(self) -> None:
        key = self.rng.choice(KEYS)
        self.log.append(f"key {key}")
        self.qtbot.keyClick(self.vp, key)

    def type_number(self) -> None:
        props = self.window.properties
        fields = sorted(props.fields)
        if not fields:
            return self.select()
        name, text = self.rng.choice(fields), self.rng.choice(TEXTS)
        self.log.append(f"type {name} {text!r}")
        edit = props.fields[name]
        if not edit.isVisible():
            return
        edit.setFocus()
        edit.selectAll()
        self.qtbot.keyClicks(edit, text)
        self.qtbot.keyClick(edit, Qt.Key.Key_Return)

    def select(self) -> None:
        sel = self.window.properties.selector
        if sel.count():
            i = self.rng.randrange(sel.count())
            self.log.append(f"select {sel.itemText(i)!r}")
            sel.activated.emit(i)

    def combo(self) -> None:
        combos = self.window.properties.combos
        if combos:
            name = self.rng.choice(sorted(combos))
            box = combos[name]
            if box.count():
                i = self.rng.randrange(box.count())
                self.log.append(f"combo {name} {i}")
                box.setCurrentIndex(i)
                box.activated.emit(i)

    def wheel(self) -> None:
        """A wheel turn over the canvas (zoom) or over a widget of the properties dock (which must
        not change unless it has focus)."""
        rng = self.rng
        targets = [self.vp] * 3 + [w for w in self.window.properties.findChildren(QWidget) if w.isVisible()]
        target = rng.choice(targets)
        pos = QPointF(rng.uniform(0, max(1, target.width() - 1)), rng.uniform(0, max(1, target.height() - 1)))
        delta = rng.choice([-360, -120, -15, 15, 120, 360])
        mods = rng.choice([Qt.KeyboardModifier.NoModifier] * 3 + [Qt.KeyboardModifier.ControlModifier])
        self.log.append(f"wheel {type(target).__name__} {delta}")
        event = QWheelEvent(pos, target.mapToGlobal(pos), QPoint(0, 0), QPoint(0, delta), Qt.MouseButton.NoButton,
                            mods, Qt.ScrollPhase.NoScrollPhase, False)
        QApplication.sendEvent(target, event)

    def play(self) -> None:
        player = self.window.player
        self.log.append("play/pause")
        player.toggle()

    def scrub(self) -> None:
        bar = self.window.scrubbar
        if bar.width() > 2:
            x = self.rng.randrange(bar.width())
            self.log.append(f"scrub {x}")
            self.qtbot.mouseClick(bar, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier,
                                  QPoint(x, bar.height() // 2))

    def ctrl_key(self) -> None:
        key = self.rng.choice(CTRL_KEYS)
        if key == Qt.Key.Key_N:   # New asks to save: the monkey discards
            self.parts.dialogs.save_changes.append("discard")
        self.log.append(f"ctrl+key {key}")
        self.qtbot.keyClick(self.vp, key, Qt.KeyboardModifier.ControlModifier)

    def handle_drag(self) -> None:
        """Drag a handle of a selected Geneva drive or rolling lever (selecting one first)."""
        ctl = self.parts.controller
        elements = [e.id for e in ctl.scene.elements if e.type in ("geneva", "rolling_lever")]
        if not elements:
            return self.click()
        eid = self.rng.choice(elements)
        ctl.set_selection([(eid, "element", eid)])
        handles = self.view.extras.handles.handles()
        if not handles:
            return None
        h = self.rng.choice(handles)
        a = self.screen(h.at)
        b = self.screen((h.at[0] + self.rng.gauss(0, 15), h.at[1] + self.rng.gauss(0, 15)))
        self.log.append(f"handle {eid}.{h.name} {a.x()},{a.y()} -> {b.x()},{b.y()}")
        self.qtbot.mouseMove(self.vp, a)
        self.qtbot.mousePress(self.vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, a)
        for k in range(1, 4):
            self.qtbot.mouseMove(self.vp, QPoint(a.x() + (b.x() - a.x()) * k // 3, a.y() + (b.y() - a.y()) * k // 3))
        self.qtbot.mouseRelease(self.vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, b)

    def place(self) -> None:
        """A Geneva drive (two clicks, maybe a slot key) or the start of a dyad, quickly."""
        name = self.rng.choice(["geneva", "geneva", "prp", "rpp", "rrr", "rrp", "crank", "rolling"])
        self.log.append(f"place {name}")
        self.view.toolbox.actions[name].trigger()
        for _ in range(self.rng.randint(1, 3)):
            self.click()
        if name == "geneva" and self.rng.random() < 0.5:
            self.qtbot.keyClick(self.vp, self.rng.choice("3456789"))

    def tick(self) -> None:
        """Some animation ticks (the player's clock moved by hand)."""
        player = self.window.player
        self.log.append("ticks")
        if not player.is_playing:
            player.play()
        for _ in range(self.rng.randint(1, 5)):
            self.clock.advance(self.rng.uniform(0.0, 0.3))
            player.tick()

    def step(self) -> None:
        """One random event; now and then a burst of several with no event processing between
        them (a user faster than the app), then what the running event loop does."""
        kinds = [self.action] * 3 + [self.tool] * 4 + [self.click] * 10 + [self.drag] * 8 + [self.key] * 4 + \
                [self.type_number] * 5 + [self.select] * 3 + [self.combo] + [self.play] + [self.scrub] * 2 + \
                [self.ctrl_key] * 2 + [self.handle_drag] * 3 + [self.place] * 3 + [self.tick] * 2 + [self.wheel] * 3
        for _ in range(self.rng.choice([1, 1, 1, 4])):
            self.rng.choice(kinds)()
        QApplication.processEvents()
        # what the running event loop does between events: widgets the panels rebuilt go away
        # (without it deleteLater'd widgets pile up and each event costs more than the last)
        QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete)


def run(parts, qtbot, events: int, seed: int = SEED, fresh: int = FRESH, on_event=None,
        on_start=None) -> tuple[Monkey, list[str]]:
    """``events`` random events on the app ``parts`` (every ``fresh``-th opens an example so the
    scene does not grow without bound); returns the monkey (its log) and the errors that reached
    sys.excepthook, each with the events before it. ``on_event(k)`` is called after each."""
    from app_fakes import FakeClock

    errors: list[str] = []
    monkey = Monkey(parts, qtbot, random.Random(seed))
    monkey.steps = 0
    monkey.clock = FakeClock()
    if on_start is not None:
        on_start(monkey)
    parts.window.player.clock = monkey.clock

    def hook(kind, value, tb):
        tail = "\n".join(monkey.log[-15:])
        errors.append("".join(traceback.format_exception(kind, value, tb)) + "\nafter:\n" + tail)

    previous, sys.excepthook = sys.excepthook, hook
    examples = sorted(k for k in parts.window.actions if k.startswith("example:"))
    try:
        for k in range(events):
            monkey.steps = k + 1
            if k % fresh == fresh - 1:   # every example in turn, from one the seed picks
                name = examples[(k // fresh + seed) % len(examples)]
                monkey.log.append(f"action {name}")
                parts.dialogs.save_changes.append("discard")
                parts.window.actions[name].trigger()
            else:
                monkey.step()
            if on_event is not None:
                on_event(k)
            if errors:
                break
    finally:
        sys.excepthook = previous
        parts.window.player.pause()
    return monkey, errors


