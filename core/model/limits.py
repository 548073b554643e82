"""The physical range of every quantity a scene may hold (the README's scene-file section).

The JSON schemas (resources/schema/*.json) state most of these as ``minimum``/``maximum``; the
parsers check what a schema cannot say (a signed speed whose magnitude has a lower bound, drawn
positions with their own message). Values outside are refused with a message naming the key,
the value and the range, before anything is solved, so no analysis meets an overflow.
"""
from __future__ import annotations

#: positions, lengths, radii, clearances, mm (1,000 km)
MAX_LENGTH_MM = 1e9
#: the smallest value of a quantity that must be positive, or of one that may be 0 but is not, by
#: unit (a roller 1e-300 mm long overflowed the contact pressure; a wheel inertia of 5e-324 kg·m²
#: made a denormal load whose contact strip underflowed to 0): lengths 1 nm, moduli 1 kPa,
#: specific wear rates 1e-12, inertias 1e-12 kg·m², moments 1e-12 N·m; a linkage's masses, loads
#: and gravity 1e-12 in their units (a 5e-324 N·m torque made the power balance read 100 %, one
#: of 1e-300 N·m an RMS driving torque of 0: issue 20, item 12)
SMALLEST = {"mm": 1e-6, "MPa": 1e-3, "mm³/(N·m)": 1e-12, "kg·m²": 1e-12, "N·m": 1e-12,
            "N": 1e-12, "kg": 1e-12, "m/s²": 1e-12, "N/mm": 1e-12, "N·s/mm": 1e-12}
#: driver or crank speed magnitude, rpm: from one turn in about 42 days to a fast spindle
MIN_RPM = 1e-3
MAX_RPM = 1e5
#: drawn angles (slide axes, wheel direction), degrees either way (100 turns)
MAX_ANGLE_DEG = 36_000.0


def tiny_problem(value: float, unit: str) -> str | None:
    """The message for a value that may be 0 but is nonzero and below :data:`SMALLEST` in size (a
    subnormal included), or None: such a value is refused, not read as 0, so the file says what
    is analysed."""
    least = SMALLEST[unit]
    if value != 0.0 and abs(value) < least:
        return f"must be 0 or at least {least:g} {unit} in size; got {value!r} {unit}"
    return None


def speed_problem(speed: float) -> str | None:
    """The message for a driver speed (rpm, signed) outside the range, or None if it is fine."""
    if speed == 0.0:
        return "must not be zero (the sign gives the direction)"
    if not MIN_RPM <= abs(speed) <= MAX_RPM:
        return (f"|speed_rpm| must lie from {MIN_RPM:g} to {MAX_RPM:g} rpm (the sign gives the "
                f"direction); got {speed:g}")
    return None
