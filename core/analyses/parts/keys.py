"""What the user can change when a part cannot be cut, named as the front end in use names it.

A part names what sizes it (:attr:`~.records.Part.keys`) in one canonical form:

- a scene key (``"slots"``, ``"drawing.wheel_bore_radius"``, ``"drawing.boss_radius"``), or
- an export option that no scene key sets, ``"option:NAME"`` (``"option:depth"``,
  ``"option:tolerance"``).

A :class:`Vocabulary` says how one front end names the export options it has: ``mechsketch
export`` by its flags (``--boss-radius``), the export dialog by its fields, ``validate`` by none
(it has no such options). :func:`name_of` turns a canonical key into the words of that front end:
a drawing key that an option of the front end also sets is named both ways ("--boss-radius or
drawing.boss_radius"), an option the front end lacks is named in words ("the export's plate
depth"), so no message names a flag or a field the user cannot find where they are.
"""
from __future__ import annotations

from dataclasses import dataclass

#: prefix of canonical keys that are export options only
OPTION = "option:"
#: export options in words, where a front end has no name for them
WORDS = {"min_web": "minimum web", "depth": "plate depth", "tolerance": "curve tolerance", "kerf": "kerf",
         "bore_key": "bore key", "fasteners": "fastener diameter", "base_plate": "base plate",
         "arcs_entities": "LINE/ARC entities", "annotate": "annotations"}


@dataclass(frozen=True)
class Vocabulary:
    """How a front end names its export options: ``options`` pairs (option, name), e.g.
    ("boss_radius", "--boss-radius"); ``where``: the front end in words, for messages."""

    options: tuple[tuple[str, str], ...] = ()
    where: str = "the Python API"

    def option(self, key: str) -> str | None:
        """The name of export option ``key`` (e.g. "min_web") here, or None if it has none."""
        return dict(self.options).get(key)


#: the Python API: options are the fields of :class:`~.build.PartOptions`
API = Vocabulary(tuple((k, f"PartOptions.{k}") for k in (
    "boss_radius", "bore_diameter", "link_width", "min_web", "tolerance", "depth", "frame", "kerf",
    "fasteners", "base_plate", "bore_key")) + (("arcs_entities", "arcs='entities'"), ("annotate", "annotate=True")),
    "the Python API")


def name_of(key: str, vocab: Vocabulary = API) -> str:
    """The words for canonical ``key`` in the front end ``vocab`` (see the module docstring)."""
    if key.startswith(OPTION):
        opt = key[len(OPTION):]
        return vocab.option(opt) or f"the export's {WORDS.get(opt, opt.replace('_', ' '))}"
    if key.startswith("drawing."):
        opt = vocab.option(key[len("drawing."):])
        if opt is not None:
            return f"{opt} or {key}"
    return key


def names_of(keys, vocab: Vocabulary = API) -> str:
    """``keys`` named (see :func:`name_of`), comma-separated, each once."""
    return ", ".join(dict.fromkeys(name_of(k, vocab) for k in keys))
