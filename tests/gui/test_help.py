"""Help (issue 24 item 8): Help › Manual (F1) opens the offline manual made from the README's
sections with its pictures; a getting-started page; F1 over a dock or over the canvas opens the
help of that dock or of the active tool; the shortcuts page lists every key of the window."""
from __future__ import annotations

from pathlib import Path

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtGui import QAction, QCursor
from PySide6.QtWidgets import QApplication, QPushButton

from mechsketch.gui.help.manual import START, load_pages, pictures_of, readme_pages, search, split_sections
from mechsketch.gui.help.topics import DOCKS, TOOLS
from mechsketch.gui.help.window import HelpWindow, manual_folder

from app_fakes import shell  # noqa: F401 - fixture

ROOT = Path(__file__).resolve().parents[2]


def press_f1_over(qtbot, window, widget) -> None:
    """Point at ``widget`` and press F1 as a user would (in the active window)."""
    activate(qtbot, window)
    QCursor.setPos(widget.mapToGlobal(widget.rect().center()))
    widget.setFocus()
    qtbot.keyClick(widget, Qt.Key.Key_F1)


def activate(qtbot, window) -> None:
    window.activateWindow()
    qtbot.waitUntil(window.isActiveWindow, timeout=20000)


def help_of(parts):
    return parts.window.help.help_window


def test_f1_over_the_properties_dock_opens_its_help(shell, qtbot):
    parts = shell()
    w = parts.window
    press_f1_over(qtbot, w, w.properties)
    h = help_of(parts)
    assert h.isVisible() and h.current() == "dock/properties"
    assert "Type a value and press Enter" in h.browser.toPlainText()


@pytest.mark.parametrize("dock", ["diagnostics", "plots"])
def test_f1_over_any_dock_opens_that_docks_help(shell, qtbot, dock):
    parts = shell()
    w = parts.window
    target = w.docks[dock].widget()
    qtbot.waitUntil(target.isVisible, timeout=20000)
    press_f1_over(qtbot, w, target)
    assert help_of(parts).current() == f"dock/{dock}"


def test_f1_over_the_canvas_opens_the_active_tools_help(shell, qtbot):
    parts = shell()
    canvas = parts.window.canvas
    activate(qtbot, parts.window)
    canvas.setFocus()
    qtbot.keyClick(canvas, Qt.Key.Key_W)                     # the Geneva tool, by its key
    assert canvas.toolbox.name == "geneva"
    press_f1_over(qtbot, parts.window, canvas.viewport())
    h = help_of(parts)
    assert h.current() == "tool/geneva"
    assert "Keys 3-9 choose the number of slots" in h.browser.toPlainText()


def test_help_manual_from_the_menu_opens_getting_started_then_where_it_was_left(shell, qtbot):
    parts = shell()
    w = parts.window
    QCursor.setPos(w.mapToGlobal(QPoint(-50, -50)))          # over nothing of the window
    w.menuBar().setFocus()
    w.actions["manual"].trigger()
    h = help_of(parts)
    assert h.current() == START
    text = h.browser.toPlainText()
    assert "Draw a four-bar" in text and "Getting started" in h.windowTitle() + text
    h.show_page("readme/command-line")
    w.actions["manual"].trigger()
    assert h.current() == "readme/command-line"
    w.actions["getting_started"].trigger()
    assert h.current() == START


def test_every_readme_section_is_a_page_with_its_text_and_pictures(qtbot):
    h = HelpWindow()
    qtbot.addWidget(h)
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    headings = [t for level, t, _ in split_sections(readme) if level in (2, 3)]
    titles = [p.title for p in h.pages.values() if p.slug.startswith("readme/")]
    assert len(titles) == len(headings) + 1 and "Command line" in titles and "Scene files" in titles
    pictures = 0
    for page in [p for p in h.pages.values() if pictures_of(p.markdown)]:
        h.show_page(page.slug)
        h.browser.document().adjustSize()                    # lays out: the pictures are loaded
        pictures += len(pictures_of(page.markdown))
        for path in pictures_of(page.markdown):
            assert (h.folder / path).is_file(), path
    assert h.browser.missing == [] and pictures >= 15
    h.show_page("readme/the-desktop-app")
    assert "The canvas (centre) is in world millimetres" in h.browser.toPlainText()


def test_the_manual_is_the_readme(tmp_path):
    """The packaged README is the repository's (a link in a checkout, a copy in a wheel)."""
    folder = manual_folder()
    assert (folder / "README.md").read_text(encoding="utf-8") == (ROOT / "README.md").read_text(encoding="utf-8")
    pages = load_pages(folder)
    assert pages[0].slug == START
    assert [p.slug for p in pages[1:]] == [p.slug for p in readme_pages((ROOT / "README.md").read_text())]


def test_every_tool_and_dock_has_help_and_every_link_lands_on_a_page(shell, qtbot):
    parts = shell()
    h = help_of(parts)
    tools = set(parts.window.canvas.toolbox.tools)
    assert tools <= set(TOOLS), tools - set(TOOLS)
    assert set(parts.window.docks) <= set(DOCKS)
    import re
    for page in list(h.pages.values()):
        for slug in re.findall(r"\(manual:/([^)]+)\.md\)", page.markdown):
            assert slug in h.pages, f"{page.slug} links to {slug}, which is not a page"


def test_the_shortcuts_page_lists_every_key_of_the_window(shell, qtbot):
    parts = shell()
    w = parts.window
    w.actions["shortcuts"].trigger()
    h = help_of(parts)
    assert h.current() == "shortcuts"
    text = h.browser.toPlainText()
    for act in w.findChildren(QAction):
        for key in act.shortcuts():
            assert key.toString() in text, (act.text(), key.toString())
    for expected in ("Ctrl+S", "F1", "Ctrl+E", "Shift+R", "Mouse wheel"):
        assert expected in text
    h.show_page(START)
    qtbot.mouseClick(h.findChild(QPushButton, "manual_keys"), Qt.MouseButton.LeftButton)
    assert "Ctrl+S" in h.browser.toPlainText()          # the window's keys, from its own button too


def test_search_filters_the_contents_and_enter_opens_the_best_page(shell, qtbot):
    parts = shell()
    parts.window.actions["getting_started"].trigger()
    h = help_of(parts)
    qtbot.keyClicks(h.search, "centrodes")
    shown = [s for s, item in h._items.items() if not item.isHidden()]
    holds = {s for s in shown if "centrode" in (h.pages[s].title + h.pages[s].markdown).lower()}
    assert holds and all(s in holds or any(h.pages[c].parent == s for c in holds) for s in shown)
    assert len(shown) < len(h._items)
    assert "page(s)" in h.hits.text()
    qtbot.keyClick(h.search, Qt.Key.Key_Return)
    assert "centrode" in h.pages[h.current()].title.lower()
    assert h.browser.textCursor().selectedText().lower() == "centrodes"   # the word is found on the page
    h.search.clear()
    assert all(not item.isHidden() for item in h._items.values())
    assert search(list(h.pages.values()), "no-such-word-anywhere") == []


def test_links_back_and_forward(shell, qtbot):
    parts = shell()
    parts.window.actions["getting_started"].trigger()
    h = help_of(parts)
    h.show_page("dock/diagnostics")
    h.browser.setSource(h.browser.source().resolved(h.browser.source()))
    h.show_page("readme/forces-analyze-forces")
    back = h.findChild(QPushButton, "manual_back")
    qtbot.mouseClick(back, Qt.MouseButton.LeftButton)
    assert h.current() == "dock/diagnostics"
    qtbot.mouseClick(h.findChild(QPushButton, "manual_forward"), Qt.MouseButton.LeftButton)
    assert h.current() == "readme/forces-analyze-forces"
    QApplication.processEvents()
