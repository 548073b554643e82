"""The manual's pages as Markdown, Qt-free: the README cut at its section headings, the
getting-started page, and search over them.

The packaged manual folder (``mechsketch/resources/manual``) holds ``README.md`` and
``pictures/`` (in a checkout, links to the repository's README.md and docs/screenshots, so the
manual is always the README; a wheel carries copies) and ``getting_started.md``. A README image
``docs/screenshots/NAME`` becomes ``pictures/NAME``.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

#: the slug of the first page the manual shows
START = "getting-started"

_HEADING = re.compile(r"^(#{1,3})\s+(.*?)\s*#*\s*$")
_FENCE = re.compile(r"^\s*(```|~~~)")
_PICTURE = re.compile(r"\]\((?:\./)?docs/screenshots/")


@dataclass(frozen=True)
class Page:
    """One page: ``slug`` names it in links (``manual:/SLUG.md``), ``level`` 1 or 2 (a section or
    a subsection), ``parent`` the slug of the section a subsection belongs to."""

    slug: str
    title: str
    markdown: str
    level: int = 1
    parent: str | None = None


def slugify(title: str) -> str:
    """``"`export`: cut-ready parts"`` -> ``"export-cut-ready-parts"``."""
    words = re.sub(r"[^0-9a-z]+", "-", title.lower().replace("`", "")).strip("-")
    return words or "section"


def plain_title(title: str) -> str:
    """A heading without its Markdown marks."""
    return re.sub(r"[`*_]", "", title).strip()


def split_sections(text: str) -> list[tuple[int, str, list[str]]]:
    """(level, heading, body lines) of each ``#``/``##``/``###`` section of Markdown ``text``;
    headings inside fenced code blocks are code, not headings."""
    out: list[tuple[int, str, list[str]]] = []
    level, title, body = 1, "", []
    fenced = False
    for line in text.splitlines():
        if _FENCE.match(line):
            fenced = not fenced
        match = None if fenced else _HEADING.match(line)
        if match:
            if title or any(s.strip() for s in body):
                out.append((level, title, body))
            level, title, body = len(match.group(1)), match.group(2), []
        else:
            body.append(line)
    out.append((level, title, body))
    return out


def readme_pages(text: str) -> list[Page]:
    """The README as pages: its introduction (the ``#`` title), each ``##`` section, and each
    ``###`` subsection under the section before it. Images point into ``pictures/``."""
    pages: list[Page] = []
    parent: str | None = None
    taken: set[str] = set()
    for level, title, body in split_sections(_PICTURE.sub("](pictures/", text)):
        name = plain_title(title) or "Overview"
        slug = slug0 = "readme/" + ("overview" if level == 1 else slugify(title))
        k = 2
        while slug in taken:
            slug, k = f"{slug0}-{k}", k + 1
        taken.add(slug)
        depth = 2 if level == 3 and parent is not None else 1
        markdown = f"# {title or 'mechsketch'}\n" + "\n".join(body).strip("\n") + "\n"
        pages.append(Page(slug, "mechsketch" if level == 1 else name, markdown, depth,
                          parent if depth == 2 else None))
        if depth == 1:
            parent = slug
    return pages


def load_pages(folder: Path) -> list[Page]:
    """The getting-started page, then the README's pages, from the manual folder."""
    start = (folder / "getting_started.md").read_text(encoding="utf-8")
    readme = (folder / "README.md").read_text(encoding="utf-8")
    first = split_sections(start)
    title = next((plain_title(t) for _lvl, t, _b in first if t), "Getting started")
    return [Page(START, title, _PICTURE.sub("](pictures/", start)), *readme_pages(readme)]


def pictures_of(markdown: str) -> list[str]:
    """The image paths a page shows (``![alt](path)``), in order."""
    return re.findall(r"!\[[^\]]*\]\(([^)\s]+)", markdown)


def search(pages: list[Page], query: str) -> list[Page]:
    """Pages holding every word of ``query`` (case-insensitive), those with a word in the title
    first; every page for an empty query."""
    words = query.lower().split()
    if not words:
        return list(pages)
    hits = [p for p in pages if all(w in (p.title + "\n" + p.markdown).lower() for w in words)]
    return sorted(hits, key=lambda p: not any(w in p.title.lower() for w in words))


def snippet(page: Page, query: str, width: int = 80) -> str:
    """The text around the first word of ``query`` in ``page`` (one line, for a result list)."""
    words = query.lower().split()
    text = re.sub(r"\s+", " ", page.markdown)
    at = text.lower().find(words[0]) if words else -1
    if at < 0:
        return text[:width]
    start = max(0, at - width // 3)
    return ("…" if start else "") + text[start:start + width] + "…"
