"""The properties panel: what is selected, with its numbers editable (every edit is one undo command).

Shows, for the linkage of the selection (or the first linkage): the selected joint's coordinates
(and a prismatic joint's axis), the selected link's dimensions (lengths, angles, slide-axis
offsets: every link, the ground's and a ternary link's included), what drives the linkage (crank,
cylinder or slider; motion law, speed, direction or stroke; "Drive this…" on a selected link or
prismatic joint that can be the input), the table of every dimension (:mod:`.linkage_dims`), and
each Assur group's assembly mode with a Flip button. A selected Geneva drive or rolling lever
(or the only element of a scene without linkages) shows its own fields instead
(:mod:`.geneva_panel`, :mod:`.rolling_panel`). A selector at the top lets the user pick a
joint, link or element without the canvas. The panel holds no model state: it reads ``controller.scene``
and changes it only through ``controller.push``.
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import Callable

from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QKeyEvent
from PySide6.QtWidgets import (QComboBox, QFormLayout, QFrame, QGroupBox, QHBoxLayout, QLabel, QLineEdit,
                               QScrollArea, QToolButton, QVBoxLayout, QWidget)

from mechsketch.core import MechsketchError, MoveJoint, ReplaceElement
from mechsketch.core.model.linkage import JointKind, Linkage

from .. import units
from ..controller import SceneController
from ..selection import ELEMENT, element_target
from mechsketch.core.solver.flip import FLIPPABLE, flip_edit
from .gears_panel import gears_boxes
from .geneva_panel import geneva_boxes
from .lazy import defer_preview
from .linkage_dims import dimensions_box, drive_button, driver_box, link_dimension_rows
from .loads_panel import joint_friction_row, link_mass_rows, loads_box
from .properties_fit import UNIT_LABEL, fit_width, keep_units_together, make_elider
from .rolling_panel import rolling_boxes
from ..qtsafe import qt_safe

Selection = tuple[str, str, str]


def fmt(value: float) -> str:
    """A number as shown in an editable field (enough digits to round-trip a typed value)."""
    return f"{value:.6f}".rstrip("0").rstrip(".") if math.isfinite(value) else "nan"


@qt_safe
class PropertiesPanel(QWidget):
    """Edits of the selection and of its linkage, as undo commands through the controller.

    ``editingDone`` is emitted when Enter has committed a field (the window gives the keyboard
    back to the canvas)."""

    editingDone = Signal()

    def __init__(self, controller: SceneController, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.selector = QComboBox()
        self.selector.setObjectName("selector")
        self.selector.activated.connect(self._on_selector)
        self._content = QWidget()
        self._content_layout = QVBoxLayout(self._content)
        self._content_layout.setContentsMargins(0, 0, 0, 0)
        scroll = QScrollArea()
        scroll.setWidgetResizable(True)
        # the content fits the dock's width (form rows wrap their field under the label when
        # narrow): one vertical scroll bar, never a sideways one (issue 24, item 5)
        scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        scroll.setFrameShape(QFrame.Shape.NoFrame)
        scroll.setWidget(self._content)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addWidget(self.selector)
        layout.addWidget(scroll)
        #: editable fields by name ("x", "y", "axis", "length:B-C", "speed"), for tests and refresh
        self.fields: dict[str, QLineEdit] = {}
        self.flip_buttons: dict[str, QToolButton] = {}
        self.buttons: dict[str, QWidget] = {}    # add/remove buttons of the loads box, by name
        self.tables: dict[str, QWidget] = {}     # the dimension table
        self.combos: dict[str, QComboBox] = {}   # choice boxes of a Geneva drive / rolling lever
        self.direction: QComboBox | None = None
        self._refreshers: list[Callable[[], None]] = []
        self._key: object = None
        self._elider = make_elider(self)
        controller.changed.connect(self._on_changed)
        controller.selectionChanged.connect(self.refresh)
        self.refresh()

    def keyPressEvent(self, event: QKeyEvent) -> None:  # noqa: N802 - Qt override
        """Enter in a field has committed it (a line edit passes Enter on): editing is done."""
        if event.key() in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
            event.accept()
            self.editingDone.emit()
            return
        super().keyPressEvent(event)

    def units_changed(self) -> None:
        """The display units changed (Edit › Preferences): rebuild, so labels and values follow."""
        self._key = None
        self.refresh()

    # -- what to show ------------------------------------------------------------------------
    def linkage(self) -> Linkage | None:
        """The linkage of the selection, else the scene's first linkage."""
        sel = self.controller.selection
        if sel:
            el = self.controller.scene.element(sel[0][0]) if sel[0][0] in self.controller.scene.ids else None
            if isinstance(el, Linkage):
                return el
        links = self.controller.linkages()
        return links[0] if links else None

    def selected(self) -> Selection | None:
        """The first selected joint or link that still exists."""
        for eid, kind, ident in self.controller.selection:
            if eid not in self.controller.scene.ids:
                continue
            el = self.controller.scene.element(eid)
            if not isinstance(el, Linkage) or ident not in (el.joint_ids if kind == "joint" else el.link_ids):
                continue
            return eid, kind, ident
        return None

    def _structure_key(self) -> object:
        eid = element_target(self.controller)
        if eid is not None:
            el = self.controller.scene.element(eid)
            return ("element", eid, el.type, getattr(el, "drive", None) is not None,
                    getattr(el, "slider_law", None) is not None)
        lk = self.linkage()
        if lk is None:
            return ("elements", self.controller.scene.ids)
        groups = ()
        res = self.controller.result(lk.id)
        if res is not None and res.plan is not None:
            groups = tuple(s.group.name for s in res.plan.steps)
        return (lk.id, lk.joint_ids, tuple((k.id, k.joints) for k in lk.links), lk.ground,
                lk.driver.link, lk.driver.kind, lk.driver.law.kind, self.selected(), groups,
                tuple(j.kind for j in lk.joints), lk.load_ids)

    def _on_changed(self, change) -> None:
        """A drag preview redraws the values a few times a second (see :func:`defer_preview`)."""
        if not defer_preview(self, change, self.refresh):
            self.refresh()

    def refresh(self, *_args) -> None:
        """Rebuild the panel if what it shows changed shape; else update the values in place."""
        self._fill_selector()
        key = self._structure_key()
        if key != self._key:
            self._key = key
            self._rebuild()
        for update in self._refreshers:
            update()
        keep_units_together(self._content)

    def _fill_selector(self) -> None:
        items: list[tuple[str, Selection | None]] = [("(nothing selected)", None)]
        for lk in self.controller.linkages():
            items += [(f"{lk.id}: joint {j}", (lk.id, "joint", j)) for j in lk.joint_ids]
            items += [(f"{lk.id}: link {k}", (lk.id, "link", k)) for k in lk.link_ids]
        kinds = {"geneva": "Geneva drive", "rolling_lever": "rolling lever", "gear_pair": "gear pair",
                 "geared_geneva": "smooth Geneva drive"}
        solved = self.controller.element_results()
        items += [(f"{e.id}: {kinds[e.type]}", (e.id, ELEMENT, e.id))
                  for e in self.controller.scene.elements if e.type in kinds and e.id in solved]
        current = self.selected()
        if current is None:
            current = next((s for s in self.controller.selection if s[1] == ELEMENT), None)
        self.selector.blockSignals(True)
        if [self.selector.itemData(i) for i in range(self.selector.count())] != [d for _, d in items]:
            self.selector.clear()
            for text, data in items:
                self.selector.addItem(text, data)
        datas = [d for _, d in items]
        self.selector.setCurrentIndex(datas.index(current) if current in datas else 0)
        self.selector.blockSignals(False)

    def _on_selector(self, index: int) -> None:
        data = self.selector.itemData(index)
        self.controller.set_selection([tuple(data)] if data else [])

    # -- building ----------------------------------------------------------------------------
    def _rebuild(self) -> None:
        self.fields.clear()
        self.flip_buttons.clear()
        self.buttons.clear()
        self.tables.clear()
        self.combos.clear()
        self.direction = None
        self._refreshers.clear()
        while self._content_layout.count():
            item = self._content_layout.takeAt(0)
            old = item.widget()
            if old is not None:   # silenced first: a focused field losing its focus as it goes
                for w in [old, *old.findChildren(QWidget)]:   # must not commit into another document
                    w.blockSignals(True)
                old.hide()
                old.deleteLater()
        lk = self.linkage()
        eid = element_target(self.controller)
        if eid is not None:
            kind = self.controller.scene.element(eid).type
            build = {"geneva": geneva_boxes, "gear_pair": gears_boxes, "geared_geneva": gears_boxes}.get(kind, rolling_boxes)
            for box in build(self, eid):
                self._content_layout.addWidget(box)
        elif lk is None:
            self._content_layout.addWidget(self._elements_box())
        else:
            sel = self.selected()
            if sel is not None and sel[1] == "joint":
                self._content_layout.addWidget(self._joint_box(lk.id, sel[2]))
            elif sel is not None and sel[1] == "link":
                self._content_layout.addWidget(self._link_box(lk.id, sel[2]))
            else:
                hint = QLabel("Select a joint or a link (on the canvas or above) to edit it.")
                hint.setWordWrap(True)
                self._content_layout.addWidget(hint)
            self._content_layout.addWidget(driver_box(self, lk.id))
            self._content_layout.addWidget(self._modes_box(lk.id))
            self._content_layout.addWidget(dimensions_box(self, lk.id))
            self._content_layout.addWidget(loads_box(self, lk.id))
        self._content_layout.addStretch(1)
        self._fit_width()

    def _fit_width(self) -> None:
        """Let every row shrink to the dock's width (issue 24, item 5: :mod:`.properties_fit`)."""
        fit_width(self._content, self._elider)

    def _elements_box(self) -> QGroupBox:
        box = QGroupBox("Scene")
        form = QFormLayout(box)
        els = self.controller.scene.elements
        if not els:
            form.addRow(QLabel("The scene is empty: draw a linkage or open an example."))
        for e in els:
            form.addRow(QLabel(e.id), QLabel(f"{e.type} (pick it above to edit it)"))
        return box

    def _field(self, name: str, read: Callable[[], float], write: Callable[[float], None]) -> QLineEdit:
        """A number field: shows ``read()``; Enter (or leaving it) with a value other than the
        model's calls ``write``. After every commit — accepted, refused or not a number — the field
        shows what the model holds (compared with the model, not with the field's last text, so
        typing the previous value back into the same field is an edit too)."""
        edit = QLineEdit()
        edit.setObjectName(name)
        edit.setMinimumWidth(70)
        self.fields[name] = edit

        def update() -> None:
            if edit.hasFocus() and edit.isModified():
                return
            try:
                text = units.format_value(read(), edit.property("unit"))   # in the display unit
            except MechsketchError:   # the joint or link went away: the panel rebuilds next
                return
            edit.setText(text)
            edit.setModified(False)

        def show_model() -> None:
            edit.setModified(False)
            update()

        def commit() -> None:
            text = edit.text().strip()
            try:
                current = units.format_value(read(), edit.property("unit"))
            except MechsketchError:   # the joint or link went away: the panel rebuilds next
                return
            if text == current:
                show_model()
                return
            try:   # typed in the display unit, or with its own (2 in, 50.8 mm); back in the model's
                value = units.parse(text, edit.property("unit"))
            except ValueError as exc:
                self.controller.message.emit(f"{name}: {exc}")
                show_model()
                return
            try:
                write(value)
            except MechsketchError as exc:
                self.controller.message.emit(f"{name}: {exc}")
            show_model()   # what the model holds now: a refused push left it as it was

        edit.editingFinished.connect(commit)
        self._refreshers.append(update)
        return edit

    def number_field(self, name: str, read: Callable[[], float], write: Callable[[float], None]) -> QLineEdit:
        """A number field (see :meth:`_field`), for the element panels."""
        return self._field(name, read, write)

    def add_refresher(self, update: Callable[[], None]) -> None:
        """Call ``update`` whenever the panel refreshes (until the next rebuild)."""
        self._refreshers.append(update)

    def row(self, edit: QWidget, unit: str) -> QWidget:
        """A field with its unit beside it."""
        return self._row(edit, unit)

    @staticmethod
    def _row(edit: QWidget, unit: str) -> QWidget:
        w = QWidget()
        h = QHBoxLayout(w)
        h.setContentsMargins(0, 0, 0, 0)
        h.addWidget(edit, 1)
        edit.setProperty("unit", unit)                # the model's unit; shown in the display unit
        unit_label = QLabel(units.display_unit(unit))
        unit_label.setObjectName(UNIT_LABEL)      # never wrapped (issue 24 item 5b: "rad/ s")
        h.addWidget(unit_label)
        return w

    def _lk(self, eid: str) -> Linkage:
        return self.controller.scene.element(eid)

    def _joint_box(self, eid: str, jid: str) -> QGroupBox:
        joint = self._lk(eid).joint(jid)
        box = QGroupBox(f"Joint {jid} ({'revolute' if joint.kind is JointKind.R else 'prismatic'})")
        form = QFormLayout(box)
        for axis, i in (("x", 0), ("y", 1)):
            def write(v: float, i: int = i) -> None:
                at = list(self._lk(eid).joint(jid).at)
                at[i] = v
                self.controller.push(MoveJoint(eid, jid, (at[0], at[1])), f"move joint {jid}")
            edit = self._field(axis, lambda i=i: self._lk(eid).joint(jid).at[i], write)
            form.addRow(f"{axis}", self._row(edit, "mm"))
        if joint.kind is JointKind.P:
            def write_axis(v: float) -> None:
                lk = self._lk(eid)
                new = lk.with_joint(replace(lk.joint(jid), axis_deg=v))
                self.controller.push(ReplaceElement(new, f"set axis of {jid}"), f"set axis of {jid}")
            edit = self._field("axis", lambda: self._lk(eid).joint(jid).axis_deg or 0.0, write_axis)
            form.addRow("slide axis", self._row(edit, "°"))
        form.addRow("links", QLabel(", ".join(self._lk(eid).links_of(jid)) or "none"))
        joint_friction_row(self, form, eid, jid)
        drive_button(self, form, eid, "joint", jid)
        return box

    def _link_box(self, eid: str, kid: str) -> QGroupBox:
        lk = self._lk(eid)
        link = lk.link(kid)
        role = " (ground)" if kid == lk.ground else " (driver)" if kid == lk.driver.link else ""
        box = QGroupBox(f"Link {kid}{role}")
        form = QFormLayout(box)
        form.addRow("joints", QLabel(", ".join(link.joints)))
        link_dimension_rows(self, form, eid, kid)
        drive_button(self, form, eid, "link", kid)
        if kid != lk.ground:
            link_mass_rows(self, form, eid, kid)
        return box

    def _modes_box(self, eid: str) -> QGroupBox:
        box = QGroupBox("Assembly modes")
        form = QFormLayout(box)
        res = self.controller.result(eid)
        if res is None or res.plan is None:
            msg = QLabel(f"not solved: {res.error}" if res is not None and res.error else "not solved")
            msg.setWordWrap(True)
            form.addRow(msg)
            return box
        for step in res.plan.steps:
            g = step.group
            label = QLabel()
            row = QWidget()
            h = QHBoxLayout(row)
            h.setContentsMargins(0, 0, 0, 0)
            h.addWidget(label, 1)
            if g.kind in FLIPPABLE:
                button = QToolButton()
                button.setText("Flip")
                button.setObjectName(f"flip:{g.name}")
                button.setToolTip("Redraw the group in its other assembly mode (lengths kept)")
                button.clicked.connect(lambda _=False, name=g.name: self.flip(eid, name))
                self.flip_buttons[g.name] = button
                h.addWidget(button)

            def show(label: QLabel = label, name: str = g.name) -> None:
                r = self.controller.result(eid)
                mode = None
                # the mode the diagnostics report, read from the solution (a drag does not wait for them)
                if r is not None and r.solution is not None and name in {x.name for x in r.solution.groups}:
                    mode = r.solution.group_output(name).mode
                label.setText("mode —" if mode is None else f"mode {mode:+.0f}")
            self._refreshers.append(show)
            form.addRow(f"{g.name}", row)
        return box

    def flip(self, eid: str, group: str) -> bool:
        """Flip ``group``'s assembly mode as one undo command; False (and a message) if refused."""
        try:
            edit = flip_edit(self._lk(eid), group)
        except MechsketchError as exc:
            self.controller.message.emit(f"cannot flip {group}: {exc}")
            return False
        return self.controller.push(edit, f"flip {group}")
