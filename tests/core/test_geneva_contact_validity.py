"""The contact model's validity range (issue 20, item 3): deformation ≪ roller radius, strip
half-width ≪ roller radius and roller length. Outside it every affected row is flagged and its
contact quantities are empty; no length, path or wear is ever negative; the CSV, the summary and
the plots say the same. References: the limits re-derived from the closed forms below, not the
module's."""
from __future__ import annotations

import csv
import io
import json
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from mechsketch.core import load_scene
from mechsketch.core.analyses.geneva import contact as contact_mod
from mechsketch.core.analyses.geneva.contact import contact
from mechsketch.core.analyses.geneva.report import analysis_table, summary
from mechsketch.core.analyses.geneva.kinematics import kinematics
from mechsketch.core.cli import main
from mechsketch.core.model.geneva import ContactModel, Drawing, Geneva, Load, Material

SOFT = "/work/shared/cases/s3/geneva_soft_roller.json"
#: the quantities that are lengths, paths, widths, pressures or wear: never negative
NON_NEGATIVE = ("strip_width", "hertz_half_width", "half_width", "deformation", "slip_speed",
                "slip_speed_invariant", "slip_path", "contact_pressure", "mean_pressure", "Rn",
                "Rn_paper", "Rn_derived")


def soft_drive(e_roller: float = 1.0, **kw) -> Geneva:
    return Geneva("g", 6, 100.0, 8.0, roller_material=Material(E=e_roller),
                  drawing=Drawing(wheel_bore_radius=1.0), **kw)


def soft_scene(tmp_path) -> str:
    """The issue's repro scene (a copy, so the test does not depend on the shared folder)."""
    data = {"format": "mechsketch.scene", "schema_version": 2, "units": "mm", "elements": [
        {"type": "geneva", "id": "indexer", "slots": 6, "center_distance": 100.0, "roller_radius": 8.0,
         "roller_length": 10.0, "speed_rpm": 95.49,
         "material": {"roller": {"E": 1.0, "poisson": 0.3}, "wheel": {"E": 210000.0, "poisson": 0.3}},
         "samples": 3600}]}
    path = tmp_path / "soft.json"
    path.write_text(json.dumps(data))
    return str(path)


def reference_ratios(el: Geneva, rn: np.ndarray) -> dict[str, np.ndarray]:
    """Δ/r_p, b/r_p and b/l at normal forces ``rn`` (N), from the notes' formulas directly."""
    rp, length = el.roller_radius, el.roller_length
    e1, n1 = el.roller_material.E, el.roller_material.poisson
    e2, n2 = el.wheel_material.E, el.wheel_material.poisson
    estar = 1 / ((1 - n1 ** 2) / e1 + (1 - n2 ** 2) / e2)
    epair = 2 * e1 * e2 / (e1 + e2)
    a = 2.16 * np.sqrt(rn * 2 * rp / (length * epair))
    b_h = np.sqrt(4 * rn * rp / (math.pi * length * estar))
    with np.errstate(divide="ignore", invalid="ignore"):
        delta = np.where(rn > 0, 4 * rn / length * (1 - n1 ** 2) / e1 * (0.41 + np.log(4 * rp / a)), 0.0)
    b = np.maximum(a / 2, b_h)   # the default model's half-width a/2 and the pressure's Hertz b
    return {"deformation": delta / rp, "half_width_radius": b / rp, "half_width_length": b / length}


def test_soft_roller_rows_are_flagged_and_nothing_is_negative():
    el = soft_drive()
    c = contact(el, 3600, ContactModel())
    e = c.engaged
    for name in NON_NEGATIVE:
        col = getattr(c, name)
        assert not np.any(col[np.isfinite(col)] < 0), name
    ref = reference_ratios(el, c.Rn[e])
    lim = c.validity
    inside = ((ref["deformation"] <= lim.deformation_limit) & (ref["half_width_radius"] <= lim.half_width_limit)
              & (ref["half_width_length"] <= lim.half_width_limit))
    assert np.array_equal(c.contact_valid[e], inside)
    assert not np.any(c.contact_valid[~e])
    assert (~inside).sum() > 0.5 * e.sum()   # E = 1 MPa: most of the engagement is outside
    assert not lim.ok and lim.invalid_rows == int((~inside).sum())
    bad = e & ~c.contact_valid
    for name in ("strip_width", "hertz_half_width", "half_width", "deformation", "slip_speed",
                 "slip_speed_invariant", "contact_pressure", "mean_pressure"):
        assert np.all(np.isnan(getattr(c, name)[bad])), name
    # the running slip path is known only up to the first row outside the range
    first_bad = np.nonzero(bad)[0][0]
    rows = np.nonzero(e)[0]
    assert np.all(np.isnan(c.slip_path[rows[rows >= first_bad]]))
    assert np.all(np.diff(c.slip_path[rows[rows < first_bad]]) >= 0)
    # the per-engagement totals, the wear invariant and the life need the whole engagement
    assert math.isnan(c.slip_path_total) and math.isnan(c.slip_path_total_trapezoid)
    assert np.all(np.isnan(c.wear_invariant)) and math.isnan(c.life.cycles)
    assert math.isnan(c.life.depth_drive) and math.isnan(c.pressure_max)
    # the rigid-body statics stay: the normal force, the moment, the rolling ratio
    assert np.all(np.isfinite(c.Rn[e])) and np.all(np.isfinite(c.rolling_ratio[e]))
    # the largest ratios reached are reported
    assert lim.max_deformation_ratio == pytest.approx(ref["deformation"].max(), rel=1e-9)
    assert lim.max_half_width_length_ratio == pytest.approx(ref["half_width_length"].max(), rel=1e-9)


def test_normal_force_limit_is_where_the_first_ratio_reaches_its_limit():
    """R_n,lim is the force at which the first ratio reaches its limit: rows with R_n below it are
    valid, above it not; checked against bisection on the reference ratios."""
    for e_roller in (1.0, 30.0, 800.0, 210000.0):
        el = soft_drive(e_roller)
        c = contact(el, 720, ContactModel())
        lim = c.validity
        lo, hi = 0.0, 1e12
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            r = reference_ratios(el, np.array([mid]))
            ok = (r["deformation"][0] <= lim.deformation_limit and r["half_width_radius"][0] <= lim.half_width_limit
                  and r["half_width_length"][0] <= lim.half_width_limit)
            lo, hi = (mid, hi) if ok else (lo, mid)
        assert lim.rn_limit == pytest.approx(lo, rel=1e-9), e_roller
        e = c.engaged
        assert np.array_equal(c.contact_valid[e], c.Rn[e] <= lim.rn_limit * (1 + 1e-12))
        assert lim.ok == (lim.rn_peak <= lim.rn_limit)


def test_a_drive_just_inside_keeps_every_row_and_one_just_outside_loses_the_totals():
    """A roller modulus chosen so that the engagement's peak force sits at the limit: 0.1 % stiffer
    is valid everywhere (totals finite and non-negative), 0.1 % softer flags the peak rows."""
    el = soft_drive(210000.0)
    peak = contact(el, 720, ContactModel()).validity.rn_peak
    lo, hi = 1e-3, 210000.0   # the modulus at which rn_limit == peak, by bisection on the module
    for _ in range(80):
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if contact(soft_drive(mid), 16, ContactModel()).validity.rn_limit >= peak else (mid, hi)
    inside = contact(soft_drive(hi * 1.001), 720, ContactModel())
    outside = contact(soft_drive(lo * 0.999), 720, ContactModel())
    assert inside.validity.ok and inside.contact_valid[inside.engaged].all()
    assert inside.slip_path_total > 0 and np.isfinite(inside.life.cycles) and inside.pressure_max > 0
    assert not outside.validity.ok and math.isnan(outside.slip_path_total)
    assert 0 < outside.validity.invalid_rows < outside.engaged.sum()


def test_default_steel_drive_is_inside_with_margin():
    c = contact(soft_drive(210000.0, speed_rpm=300 / math.pi), 3600, ContactModel())
    v = c.validity
    assert v.ok and v.invalid_rows == 0 and c.contact_valid[c.engaged].all()
    assert v.max_deformation_ratio < 1e-3 and v.max_half_width_radius_ratio < 0.01
    assert v.rn_limit > 100 * v.rn_peak


@settings(max_examples=60, deadline=None)
@given(e_roller=st.floats(1e-3, 1e7), e_wheel=st.floats(1e-3, 1e7), nu=st.floats(-0.9, 0.49),
       inertia=st.one_of(st.just(0.0), st.floats(1e-12, 5)),   # the model's range: 0 or at least 1e-12 kg·m²
       mext=st.floats(-50, 50), z=st.integers(3, 10),
       model=st.sampled_from([ContactModel(), ContactModel(half_width="hertz"),
                              ContactModel(half_width="paper_full", slip_radius="undeformed"),
                              ContactModel(normal_force="paper")]))
def test_no_negative_length_path_or_wear_anywhere(e_roller, e_wheel, nu, inertia, mext, z, model):
    el = Geneva("g", z, 100.0, 3.0, roller_material=Material(E=e_roller, poisson=nu),
                wheel_material=Material(E=e_wheel), drawing=Drawing(wheel_bore_radius=1.0),
                load=Load(wheel_inertia=inertia, external_moment=mext if abs(mext) > 1e-9 else 0.0,
                          journal_radius=3.0))
    with np.errstate(divide="raise", over="raise", invalid="raise", under="ignore"):   # no inf or NaN made
        c = contact(el, 400, model)
    for name in NON_NEGATIVE:
        col = getattr(c, name)
        assert not np.any(col[np.isfinite(col)] < 0), name
    ok = c.contact_valid
    for name in ("strip_width", "hertz_half_width", "deformation", "contact_pressure"):
        assert np.all(np.isfinite(getattr(c, name)[ok])), name
    # the running slip path: finite up to the first flagged row, empty from there on
    rows = np.nonzero(c.engaged)[0]
    flagged = rows[~ok[rows]]
    before = rows[rows < flagged[0]] if flagged.size else rows
    assert np.all(np.isfinite(c.slip_path[before])) and np.all(np.diff(c.slip_path[before]) >= 0)
    if flagged.size:
        assert np.all(np.isnan(c.slip_path[rows[rows >= flagged[0]]]))
    v = c.validity
    assert np.all(c.deformation[ok] <= v.deformation_limit * el.roller_radius * (1 + 1e-9))
    b = np.maximum(c.strip_width[ok] / 2, c.hertz_half_width[ok])   # the physical half-width, either estimate
    assert np.all(b <= v.half_width_limit * min(el.roller_radius, el.roller_length) * (1 + 1e-9))
    for x in (c.slip_path_total, c.slip_path_total_trapezoid, c.life.depth_drive, c.life.depth_brake,
              c.life.cycles):
        assert math.isnan(x) or x >= 0
    assert v.ok == bool(ok[c.engaged].all())
    if v.ok:
        assert math.isfinite(c.slip_path_total)


def test_cli_csv_summary_and_api_agree_on_the_soft_roller(tmp_path, capsys):
    path = soft_scene(tmp_path)
    assert main(["analyze", path, "--csv", "-"]) == 0
    out, _ = capsys.readouterr()
    rows = list(csv.reader(io.StringIO(out)))
    head, rows = rows[0], rows[1:]
    col = {h: k for k, h in enumerate(head)}
    assert "contact_valid" in col
    el = load_scene(path).element("indexer")
    c = contact(el, el.samples, el.model)
    for k, r in enumerate(rows):
        assert r[col["contact_valid"]] == ("1" if c.contact_valid[k] else "0")
        assert r[col["wear_invariant"]] == ""   # T_i needs the whole engagement's L_s
        for name in ("strip_width", "deformation", "slip_path", "contact_pressure"):
            cell, value = r[col[name]], getattr(c, name)[k]
            if not c.contact_valid[k]:
                assert cell == "", (k, name)
            assert (cell == "") == bool(np.isnan(value)) and (cell == "" or float(cell) == value >= 0)
        if r[col["engaged"]] == "1":
            assert float(r[col["Rn"]]) == c.Rn[k] >= 0
    assert main(["analyze", path, "--summary"]) == 0
    text, _ = capsys.readouterr()
    assert "−" not in text.split("slip path per engagement")[1].split("\n")[0]
    assert "-229" not in text and "L_s = 0" not in text and "nan" not in text.lower()
    assert "outside the contact model's validity range" in text
    assert f"{c.validity.invalid_rows} of {int(c.engaged.sum())} engaged rows" in text
    assert "Δ/r_p up to" in text and "b/l up to" in text
    assert "not computed" in text   # L_s, T_i and the life


def test_summary_of_a_valid_drive_states_the_range():
    el = soft_drive(210000.0)
    kin, con = kinematics(el, 720), contact(el, 720, el.model)
    text = summary(el, kin, con)
    assert "validity range" in text and "within it at every engaged row" in text
    table = analysis_table(kin, con)
    assert table.column("contact_valid").sum() == con.engaged.sum()


def test_limits_are_module_constants_stated_in_the_assumptions():
    assert contact_mod.DEFORMATION_LIMIT == 0.05 and contact_mod.HALF_WIDTH_LIMIT == 0.1
    text = " ".join(contact(soft_drive(210000.0), 100, ContactModel()).assumptions)
    assert "Δ ≤ 0.05·r_p" in text and "b ≤ 0.1·r_p" in text and "b ≤ 0.1·l" in text
