"""The help window: the manual's contents, search, and a browser that shows a page with its pictures.

Pages are addressed as ``manual:/SLUG.md``; the browser (:class:`ManualBrowser`) serves them from
the pages in memory and the pictures from the manual folder, scaled to the page's width, so links,
Back and Forward work as in a web browser and nothing is fetched from the network.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from PySide6.QtCore import QSize, Qt, QUrl
from PySide6.QtGui import QImage, QKeySequence, QTextDocument
from PySide6.QtWidgets import (QHBoxLayout, QLabel, QLineEdit, QPushButton, QSplitter, QTextBrowser,
                               QTreeWidget, QTreeWidgetItem, QVBoxLayout, QWidget)

from mechsketch import resources

from .manual import START, Page, load_pages, search, snippet
from .topics import DOCKS, TOOLS, shortcuts_page, topic_page
from ..qtsafe import qt_safe

SCHEME = "manual"


def manual_folder() -> Path:
    """The packaged manual: README.md, getting_started.md, pictures/."""
    return Path(str(resources._root())) / "manual"


def page_url(slug: str) -> QUrl:
    return QUrl(f"{SCHEME}:/{slug}.md")


def slug_of(url: QUrl) -> str | None:
    """The page slug a ``manual:`` URL names (None for another scheme)."""
    if url.scheme() != SCHEME:
        return None
    path = url.path().lstrip("/")
    return path[:-3] if path.endswith(".md") else path


@qt_safe
class ManualBrowser(QTextBrowser):
    """A text browser whose ``manual:`` pages and pictures come from memory and the manual folder."""

    def __init__(self, pages: dict[str, Page], pictures: Path, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.pages = pages
        self.pictures = pictures
        self.setOpenLinks(True)
        self.setOpenExternalLinks(False)
        self.missing: list[str] = []    # pictures a page asked for that are not there

    def loadResource(self, kind: int, url: QUrl):  # noqa: N802 - Qt override
        if kind == QTextDocument.ResourceType.MarkdownResource or url.path().endswith(".md"):
            slug = slug_of(url)
            page = self.pages.get(slug) if slug is not None else None
            if page is not None:
                return page.markdown
            return f"# Not in the manual\n\nThere is no page `{url.toString()}`.\n"
        if kind == QTextDocument.ResourceType.ImageResource:
            return self._picture(url)
        return super().loadResource(kind, url)

    def _picture(self, url: QUrl):
        name = Path(url.path()).name
        path = self.pictures / name
        image = QImage(str(path)) if path.is_file() else QImage()
        if image.isNull():
            self.missing.append(name)
            return None
        width = max(240, self.viewport().width() - 24)
        return image.scaledToWidth(width, Qt.TransformationMode.SmoothTransformation) \
            if image.width() > width else image


@qt_safe
class HelpWindow(QWidget):
    """The manual in a window of its own: contents (left) with a search field, the page (right),
    Back, Forward and Start. :meth:`show_page` opens a page by slug."""

    def __init__(self, folder: Path | None = None, parent: QWidget | None = None,
                 shortcuts: Callable[[], list[tuple[str, str, str]]] | None = None) -> None:
        super().__init__(parent, Qt.WindowType.Window)
        self._shortcuts = shortcuts     # the window's (menu, command, keys), read when shown
        self.setObjectName("helpWindow")
        self.setWindowTitle("mechsketch manual")
        self.resize(1000, 720)
        self.folder = folder or manual_folder()
        pages = load_pages(self.folder)
        pages += [topic_page("tool", n) for n in TOOLS] + [topic_page("dock", n) for n in DOCKS]
        self.pages: dict[str, Page] = {p.slug: p for p in pages}
        self.pages["shortcuts"] = shortcuts_page([])
        self.browser = ManualBrowser(self.pages, self.folder / "pictures")
        self.browser.setObjectName("manualPage")
        self.browser.sourceChanged.connect(self._follow)
        self.search = QLineEdit()
        self.search.setObjectName("manualSearch")
        self.search.setPlaceholderText("Search the manual…")
        self.search.setClearButtonEnabled(True)
        self.search.textChanged.connect(self._filter)
        self.search.returnPressed.connect(self._open_first_hit)
        self.contents = QTreeWidget()
        self.contents.setObjectName("manualContents")
        self.contents.setHeaderHidden(True)
        self.contents.itemActivated.connect(self._open_item)
        self.contents.itemClicked.connect(self._open_item)
        self.hits = QLabel()
        self._items: dict[str, QTreeWidgetItem] = {}
        self._fill()
        self._layout()
        self.show_page(START)

    # -- layout ------------------------------------------------------------------------------
    def _layout(self) -> None:
        left = QWidget()
        column = QVBoxLayout(left)
        column.setContentsMargins(0, 0, 0, 0)
        column.addWidget(self.search)
        column.addWidget(self.hits)
        column.addWidget(self.contents, 1)
        buttons = QHBoxLayout()
        made: dict[str, QPushButton] = {}
        for name, text, slot, key in (("back", "◀ Back", self.browser.backward, QKeySequence.StandardKey.Back),
                                      ("forward", "Forward ▶", self.browser.forward,
                                       QKeySequence.StandardKey.Forward),
                                      ("start", "Getting started", lambda: self.show_page(START), None),
                                      ("keys", "Shortcuts", lambda: self.show_page("shortcuts"), None)):
            button = QPushButton(text)
            button.setObjectName(f"manual_{name}")
            button.clicked.connect(lambda _c=False, s=slot: s())
            if key is not None:
                button.setShortcut(QKeySequence(key))
            buttons.addWidget(button)
            made[name] = button
        for name, available in (("back", self.browser.backwardAvailable),
                                ("forward", self.browser.forwardAvailable)):
            made[name].setEnabled(False)
            available.connect(made[name].setEnabled)
        buttons.addStretch(1)
        right = QWidget()
        page = QVBoxLayout(right)
        page.setContentsMargins(0, 0, 0, 0)
        page.addLayout(buttons)
        page.addWidget(self.browser, 1)
        split = QSplitter()
        split.addWidget(left)
        split.addWidget(right)
        split.setSizes([260, 740])
        outer = QVBoxLayout(self)
        outer.setContentsMargins(6, 6, 6, 6)
        outer.addWidget(split)

    def sizeHint(self) -> QSize:  # noqa: N802 - Qt override
        return QSize(1000, 720)

    def _fill(self) -> None:
        """The contents tree: the getting-started page, the README's sections and subsections, the
        shortcuts, then the tools and docks."""
        self.contents.clear()
        self._items.clear()
        groups: dict[str, QTreeWidgetItem] = {}
        for slug, page in self.pages.items():
            if slug.startswith(("tool/", "dock/")):
                kind = "Tools" if slug.startswith("tool/") else "Docks"
                if kind not in groups:
                    groups[kind] = QTreeWidgetItem(self.contents, [kind])
                parent = groups[kind]
            else:
                parent = self._items.get(page.parent) if page.parent else None
            item = QTreeWidgetItem(parent if parent is not None else self.contents, [page.title])
            item.setData(0, Qt.ItemDataRole.UserRole, slug)
            item.setToolTip(0, page.title)
            self._items[slug] = item

    # -- pages -------------------------------------------------------------------------------
    def show_page(self, slug: str) -> None:
        """Show page ``slug`` (a README section ``readme/...``, ``tool/NAME``, ``dock/NAME``,
        ``shortcuts`` or the start page) and raise the window."""
        if slug == "shortcuts" and self._shortcuts is not None:
            self.pages["shortcuts"] = shortcuts_page(self._shortcuts())
        if slug not in self.pages and "/" in slug:
            kind, name = slug.split("/", 1)
            if kind in ("tool", "dock"):
                self.pages[slug] = topic_page(kind, name)
        self.browser.setSource(page_url(slug), QTextDocument.ResourceType.MarkdownResource)
        self.show()
        self.raise_()
        self.activateWindow()

    def current(self) -> str | None:
        """The slug of the page shown."""
        return slug_of(self.browser.source())

    def _follow(self, url: QUrl) -> None:
        slug = slug_of(url)
        item = self._items.get(slug) if slug else None
        if item is not None:
            self.contents.setCurrentItem(item)
        if self.search.text().strip():
            self.browser.find(self.search.text().split()[0])

    def _open_item(self, item: QTreeWidgetItem, _column: int = 0) -> None:
        slug = item.data(0, Qt.ItemDataRole.UserRole)
        if slug:
            self.show_page(slug)

    # -- search ------------------------------------------------------------------------------
    def _filter(self, text: str) -> None:
        """Show only the pages holding every word typed (their parents stay as headings)."""
        found = {p.slug for p in search(list(self.pages.values()), text)}
        for slug, item in self._items.items():
            item.setHidden(slug not in found)
            if slug in found and item.parent() is not None:
                item.parent().setHidden(False)
                item.parent().setExpanded(bool(text.strip()))
        first = self.first_hit()
        self.hits.setText("" if not text.strip() else
                          f"{len(found)} page(s)" + (f": {snippet(self.pages[first], text, 60)}" if first else ""))

    def first_hit(self) -> str | None:
        """The slug of the best page for the search text (None: no page or no text)."""
        text = self.search.text()
        if not text.strip():
            return None
        hits = search(list(self.pages.values()), text)
        return hits[0].slug if hits else None

    def _open_first_hit(self) -> None:
        slug = self.first_hit()
        if slug is not None:
            self.show_page(slug)
