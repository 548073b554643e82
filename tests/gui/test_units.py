"""gui/units.py: display units for lengths (mm, in), angles (°, rad) and speeds (rpm, rad/s); the
model stays in mm, ° and rpm. Checked against the definitions (1 in = 25.4 mm exactly, π rad =
180°, 1 rpm = 2π/60 rad/s), round trips with hypothesis, typed unit words and arithmetic."""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mechsketch.gui import units
from mechsketch.gui.units import Units, display_unit, format_value, parse, to_display, to_model

INCH = Units(length="in")
RAD = Units(angle="rad", speed="rad/s")


def test_the_definitions():
    assert to_display(25.4, "mm", INCH) == 1.0
    assert to_display(180.0, "°", RAD) == pytest.approx(math.pi, rel=1e-15)
    assert to_display(60.0, "rpm", RAD) == pytest.approx(2 * math.pi, rel=1e-15)
    assert to_display(254.0, "mm/s", INCH) == pytest.approx(10.0, rel=1e-15)
    assert to_display(25.4, "mm/s²", INCH) == pytest.approx(1.0, rel=1e-15)
    assert to_display(1.0, "N/mm", INCH) == pytest.approx(25.4, rel=1e-15)     # N per inch is more
    assert to_display(645.16, "mm²", INCH) == pytest.approx(1.0, rel=1e-15)
    for unit in ("N", "N·m", "kg", "kg·m²", "s", "cycles/min"):
        assert to_display(3.5, unit, INCH) == 3.5 and display_unit(unit, INCH) == unit
    assert [display_unit(u, INCH) for u in ("mm", "mm/s", "mm/s²", "N/mm", "N·s/mm")] == \
        ["in", "in/s", "in/s²", "N/in", "N·s/in"]
    assert display_unit("°", RAD) == "rad" and display_unit("rpm", RAD) == "rad/s"
    assert display_unit("mm") == "mm" and display_unit("°") == "°" and display_unit("rpm") == "rpm"


def test_typed_values_in_the_shown_unit_or_with_their_own():
    assert parse("2", "mm", INCH) == 50.8
    assert parse("2 in", "mm") == 50.8 and parse('2"', "mm") == 50.8 and parse("1 ft", "mm") == 304.8
    assert parse("50.8 mm", "mm", INCH) == 50.8 and parse("5 cm", "mm", INCH) == 50.0
    assert parse("1/4", "mm", INCH) == pytest.approx(6.35, rel=1e-15)
    assert parse("2*25.4 + 3", "mm") == pytest.approx(53.8, rel=1e-15)
    assert parse("-(1+1)/4", "mm") == -0.5
    assert parse("1.5 rad", "°") == pytest.approx(math.degrees(1.5), rel=1e-15)
    assert parse("90", "°", RAD) == pytest.approx(90 * 180 / math.pi, rel=1e-15)
    assert parse("10 rad/s", "rpm") == pytest.approx(600 / (2 * math.pi), rel=1e-15)
    assert parse("3,5", "mm") == 3.5                          # a decimal comma
    assert parse("7", "N") == 7.0 and parse("7", None) == 7.0


@pytest.mark.parametrize("text, unit, says", [
    ("abc", "mm", "not a number"), ("1/0", "mm", "divides by zero"), ("2 rad", "mm", "not a unit of this field"),
    ("3 mm", "°", "not a unit of this field"), ("1e400", "mm", "not a finite number"),
    ("__import__('os')", "mm", "not a number"), ("2**10", "mm", "not a number"), ("", "mm", "not a number"),
])
def test_bad_input_says_what_is_wrong(text, unit, says):
    with pytest.raises(ValueError, match=says):
        parse(text, unit)


@settings(max_examples=300, deadline=None)
@given(value=st.floats(-1e9, 1e9, allow_nan=False), unit=st.sampled_from(["mm", "°", "rpm", "mm/s"]),
       shown=st.sampled_from([Units(), INCH, RAD, Units("in", "rad", "rad/s")]))
def test_what_is_shown_reads_back_as_the_model_value(value, unit, shown):
    """format -> parse returns the model value to the field's 6 decimals (in the model unit)."""
    back = parse(format_value(value, unit, shown), unit, shown)
    assert abs(back - value) <= 1e-6 * max(1.0, abs(value)) + 5e-7
    assert to_model(to_display(value, unit, shown), unit, shown) == pytest.approx(value, rel=1e-15, abs=1e-300)


def test_subscribers_hear_a_change_and_dead_ones_drop_out():
    heard = []

    class Panel:
        def changed(self):
            heard.append(units.current())

    panel, gone = Panel(), Panel()
    units.subscribe(panel.changed)
    units.subscribe(gone.changed)
    del gone
    try:
        units.set_current(INCH)
        units.set_current(INCH)                               # no change: no call
        assert heard == [INCH]
    finally:
        units.set_current(Units())
    assert heard == [INCH, Units()]


def test_a_unit_outside_the_choices_is_refused():
    with pytest.raises(ValueError, match="length unit 'cm'"):
        Units(length="cm")


def test_axis_labels_name_the_shown_unit():
    from mechsketch.gui.units import relabel

    both = Units("in", "rad")
    assert relabel("position (mm)", both) == "position (in)"
    assert relabel("velocity (mm/s)", both) == "velocity (in/s)"
    assert relabel("acceleration (mm/s²)", both) == "acceleration (in/s²)"
    assert relabel("crank angle φ (°, from the line of centres)", both) == "crank angle φ (rad, from the line of centres)"
    assert relabel("k53 (mm/rad)", both) == "k53 (in/rad)"
    assert relabel("Rn (N)", both) == "Rn (N)" and relabel("ω (rad/s)", both) == "ω (rad/s)"
    assert relabel("position (mm)") == "position (mm)"
