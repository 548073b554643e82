"""Display units, Qt-free: what the panels show and read, while the model stays in millimetres,
degrees and rpm.

A field names the unit its model value is in (``"mm"``, ``"°"``, ``"rpm"``, ``"mm/s"``, ``"N/mm"`` …);
:func:`to_display`, :func:`display_unit` and :func:`format_value` turn a model value into what the
user sees in the current :class:`Units`, and :func:`parse` turns what the user typed back into
the model's unit. A typed value may name its own unit (``2 in``, ``50.8 mm``, ``1.5 rad``,
``30 rpm``) and may be simple arithmetic (``1/4``, ``2*25.4 + 3``). Units other than lengths,
angles and speeds (N, N·m, kg, kg·m², s …) are shown as they are.

The current units are process-wide (:func:`current`, :func:`set_current`); panels that show
values register a callback with :func:`subscribe` (held weakly: a deleted panel drops out).
Inch is a display and entry unit only: files always hold millimetres.
"""
from __future__ import annotations

import ast
import math
import operator
import re
import weakref
from dataclasses import dataclass
from typing import Callable

MM_PER_IN = 25.4
LENGTHS = ("mm", "in")
ANGLES = ("deg", "rad")
SPEEDS = ("rpm", "rad/s")


@dataclass(frozen=True)
class Units:
    """``length`` "mm" | "in", ``angle`` "deg" | "rad", ``speed`` "rpm" | "rad/s"."""

    length: str = "mm"
    angle: str = "deg"
    speed: str = "rpm"

    def __post_init__(self) -> None:
        for name, value, allowed in (("length", self.length, LENGTHS), ("angle", self.angle, ANGLES),
                                     ("speed", self.speed, SPEEDS)):
            if value not in allowed:
                raise ValueError(f"{name} unit {value!r} is not one of {', '.join(allowed)}")


MODEL = Units()
_current = MODEL
_listeners: list[weakref.ref] = []


def current() -> Units:
    """The units the app shows now."""
    return _current


def set_current(units: Units) -> None:
    """Show ``units`` from now on; every subscribed callback is called if they changed."""
    global _current
    if units == _current:
        return
    _current = units
    for ref in list(_listeners):
        callback = ref()
        if callback is None:
            _listeners.remove(ref)
        else:
            callback()


def subscribe(callback: Callable[[], None]) -> None:
    """Call ``callback()`` when the units change (a bound method is held weakly)."""
    ref = weakref.WeakMethod(callback) if hasattr(callback, "__self__") else weakref.ref(callback)
    _listeners.append(ref)


# -- conversion ----------------------------------------------------------------------------
def _length_power(unit: str) -> tuple[str, int] | None:
    """(the unit with its length part as ``{L}``, the length's power) for a unit built on mm."""
    if unit == "mm":
        return "{L}", 1
    if unit in ("mm²", "mm^2"):
        return "{L}²", 2
    m = re.fullmatch(r"mm(/s²|/s|/rad)", unit)
    if m:
        return "{L}" + m.group(1), 1
    m = re.fullmatch(r"(N|N·s|N·m)/mm", unit)
    if m:
        return m.group(1) + "/{L}", -1
    return None


def _scale(unit: str | None, units: Units | None = None) -> tuple[float, float]:
    """(num, den): a field in model unit ``unit`` shows ``value * num / den`` (two numbers, so
    25.4 mm is exactly 1 in)."""
    u = units or _current
    if not unit:
        return 1.0, 1.0
    if unit in ("°", "deg", "°/s"):
        return (math.pi, 180.0) if u.angle == "rad" else (1.0, 1.0)
    if unit == "rpm":
        return (2.0 * math.pi, 60.0) if u.speed == "rad/s" else (1.0, 1.0)
    lp = _length_power(unit)
    if lp is not None and u.length == "in":
        return (1.0, MM_PER_IN ** lp[1]) if lp[1] > 0 else (MM_PER_IN ** -lp[1], 1.0)
    return 1.0, 1.0


def factor(unit: str, units: Units | None = None) -> float:
    """Display value per model value for a field in model unit ``unit``."""
    num, den = _scale(unit, units)
    return num / den


def display_unit(unit: str, units: Units | None = None) -> str:
    """The unit the user sees for a field in model unit ``unit``."""
    u = units or _current
    if unit in ("°", "deg"):
        return "rad" if u.angle == "rad" else "°"
    if unit == "°/s":
        return "rad/s" if u.angle == "rad" else "°/s"
    if unit == "rpm":
        return u.speed
    lp = _length_power(unit)
    if lp is not None:
        return lp[0].replace("{L}", u.length)
    return unit


def to_display(value: float, unit: str | None, units: Units | None = None) -> float:
    """A model value in ``unit`` as shown (None or an unknown unit: unchanged)."""
    num, den = _scale(unit, units)
    return value * num / den


def to_model(value: float, unit: str | None, units: Units | None = None) -> float:
    """A shown value back in the model's ``unit``."""
    num, den = _scale(unit, units)
    return value * den / num


def format_value(value: float, unit: str | None = None, units: Units | None = None, digits: int = 6) -> str:
    """A model value as shown in an editable field: ``digits`` decimals, trailing zeros dropped
    (inches and radians get two more, so a millimetre value survives the round trip to 1e-6)."""
    if not math.isfinite(value):
        return "nan"
    shown = to_display(value, unit, units)
    extra = 0 if factor(unit, units) == 1.0 else 2 if unit else 0
    text = f"{shown:.{digits + extra}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def format_length(mm: float, units: Units | None = None, digits: int = 2) -> str:
    """A length for a label: ``"12.50 mm"`` or ``"0.49 in"``."""
    u = units or _current
    return f"{to_display(mm, 'mm', u):.{digits + (2 if u.length == 'in' else 0)}f} {u.length}"


_LABEL_UNIT = re.compile(r"\((mm/s²|mm/s|mm/rad|mm|°)(?=[,)])")


def relabel(label: str, units: Units | None = None) -> str:
    """An axis label or column title with its model unit in brackets shown in the display unit:
    ``"position (mm)"`` -> ``"position (in)"``, ``"crank angle φ (°, from …)"`` -> ``"(rad, from …)"``."""
    return _LABEL_UNIT.sub(lambda m: "(" + display_unit(m.group(1), units), label)


# -- parsing -------------------------------------------------------------------------------
#: unit words a typed value may carry: word -> (kind, model units per word)
_WORDS: dict[str, tuple[str, float]] = {
    "mm": ("length", 1.0), "cm": ("length", 10.0), "m": ("length", 1000.0), "in": ("length", MM_PER_IN),
    '"': ("length", MM_PER_IN), "inch": ("length", MM_PER_IN), "ft": ("length", 304.8),
    "°": ("angle", 1.0), "deg": ("angle", 1.0), "rad": ("angle", 180.0 / math.pi),
    "rpm": ("speed", 1.0), "rad/s": ("speed", 60.0 / (2.0 * math.pi)),
}
_KIND = {"mm": "length", "°": "angle", "deg": "angle", "rpm": "speed"}
_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv}


def _arithmetic(text: str) -> float:
    """A number, or + - * / and brackets of numbers (nothing else is evaluated)."""
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError:
        raise ValueError(f"{text!r} is not a number") from None

    def value(node: ast.AST) -> float:
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
                and not isinstance(node.value, bool):
            return float(node.value)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
            v = value(node.operand)
            return -v if isinstance(node.op, ast.USub) else v
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            try:
                return _OPS[type(node.op)](value(node.left), value(node.right))
            except ZeroDivisionError:
                raise ValueError(f"{text!r} divides by zero") from None
        raise ValueError(f"{text!r} is not a number")

    return value(tree.body)


def parse(text: str, unit: str | None = None, units: Units | None = None) -> float:
    """What the user typed into a field whose model value is in ``unit``, in that unit.

    A bare number is in the unit shown; a number followed by a unit word (mm, cm, m, in, ", ft;
    °, deg, rad; rpm, rad/s) is in that unit. Raises ValueError naming what is wrong."""
    raw = text.strip().replace(",", ".") if text.count(",") == 1 and "." not in text else text.strip()
    match = re.fullmatch(r"(.*?)\s*(mm|cm|m|in|inch|ft|\"|°|deg|rad/s|rad|rpm)", raw)
    body, word = (match.group(1), match.group(2)) if match and match.group(1).strip() else (raw, None)
    number = _arithmetic(body)
    if not math.isfinite(number):
        raise ValueError(f"{text!r} is not a finite number")
    if word is None:
        return to_model(number, unit, units)
    kind, per = _WORDS[word]
    if _KIND.get(unit or "") != kind:
        shown = display_unit(unit, units) if unit else "no unit"
        raise ValueError(f"{text!r}: {word} is not a unit of this field ({shown})")
    return number * per


# -- line breaking -------------------------------------------------------------------------
#: a unit as the panels show it: mm, in, °, rad/s, rad/s², rpm, N, N·m, N/mm, mm/s, kg·m², MPa, µm …
_UNIT = (r"(?:MPa|GPa|Pa|mm|µm|cm|rad|rpm|deg|kg|in|N|s|m|°|%)[²³]?"
         r"(?:[·/](?:mm|rad|kg|in|N|s|m|°)[²³]?)*")
_UNIT_TOKEN = re.compile(rf"(?<![A-Za-z]){_UNIT}(?![A-Za-z])")
_NUMBER_SPACE = re.compile(rf"(?<=[\d.])[ \u00a0](?={_UNIT}(?![A-Za-z]))")
NBSP, WORD_JOINER = "\u00a0", "\u2060"


def unbreakable(text: str) -> str:
    """``text`` with every value and its unit kept on one line when a label wraps: a no-break
    space between a number and its unit ("10 rad/s") and a word joiner after a unit's "/" (Qt may
    break a line after a slash: "rad/ s"). Idempotent; :func:`plain` undoes it."""
    text = plain(text)
    text = _UNIT_TOKEN.sub(lambda m: m.group(0).replace("/", "/" + WORD_JOINER), text)
    return _NUMBER_SPACE.sub(NBSP, text)


def plain(text: str) -> str:
    """``text`` without the no-break marks of :func:`unbreakable` (for comparisons and copying)."""
    return text.replace(WORD_JOINER, "").replace(NBSP, " ")
