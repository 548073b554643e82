"""Degenerate inputs give a number or a stated reason, never ``nan`` (issue 13, item 10), and the
Geneva running slip path is as accurate as its exact total (item 11).

* Geneva without load (J2 = 0, M_ext = 0): R_n = 0 everywhere, so the wear invariant T_i (a ratio
  R_n/L_s, 0/0) is undefined — its column is empty and the summary says why; no "φ = nan°".
* Geneva with moduli near the float limit (E = 1e300 MPa, finite): the reduced modulus
  2E1E2/(E1 + E2) overflowed to inf/inf and emptied every contact column inside the engagement.
* A far-branch rolling lever with few points: the lever met the spline profile only just before
  its start, the physical run stopped at its first sample and the summary said "nan mm".
* The Geneva ``slip_path`` column was a trapezoid sum (1e-6 off at 3,600 samples); it is now a
  Gauss–Legendre integral on every interval, checked against an mpmath quadrature, and ends at
  the exact total.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import test_rolling_reference as RR
from mechsketch.core.analyses.geneva.contact import contact
from mechsketch.core.analyses.geneva.kinematics import kinematics
from mechsketch.core.analyses.geneva.report import analysis_table, summary
from mechsketch.core.analyses.rolling.report import summary as rolling_summary
from mechsketch.core.analyses.rolling.synthesis import synthesize
from mechsketch.core.errors import GeometryError
from mechsketch.core.model.geneva import ContactModel, Drawing, Geneva, Load, Material


def _geneva(z=6, rpm=300.0 / math.pi, **kw) -> Geneva:
    return Geneva("g", z, 100.0, 8.0, drawing=Drawing(wheel_bore_radius=1.0), speed_rpm=rpm, **kw)


def _contact_columns_inside(el, n=360):
    kin = kinematics(el, n)
    con = contact(el, n, ContactModel())
    t = analysis_table(kin, con)
    inside = con.engaged
    empty = [c for c in t.columns if not np.isfinite(t.data[inside, t.columns.index(c)]).all()]
    return kin, con, empty


def test_a_geneva_without_load_states_why_the_wear_invariant_is_empty():
    el = _geneva(load=Load(wheel_inertia=0.0, external_moment=0.0))
    kin, con, empty = _contact_columns_inside(el)
    assert empty == ["wear_invariant"]
    text = summary(el, kin, con)
    assert "nan" not in text.lower()
    assert "no load" in text and "T_i" in text and "undefined" in text


def test_a_geneva_of_moduli_near_the_float_limit_has_every_contact_column():
    el = _geneva(roller_material=Material(E=1e300), wheel_material=Material(E=1e300))
    kin, con, empty = _contact_columns_inside(el)
    assert empty == []
    assert "nan" not in summary(el, kin, con).lower()
    # a rigid pair: no contact width, so no slip; the pressure is finite (and huge)
    e = con.engaged & (con.Rn > 0)
    assert np.all(con.hertz_half_width[e] < 1e-140) and np.all(np.isfinite(con.contact_pressure[e]))


def test_an_infinite_modulus_is_refused_with_its_name():
    el = _geneva(roller_material=Material(E=math.inf))
    with pytest.raises(GeometryError, match="Young's modulus"):
        contact(el, 36, ContactModel())


@pytest.mark.parametrize("points", [8, 20, 24, 40])
def test_a_far_branch_lever_with_few_points_reports_a_physical_slip_or_why_not(points):
    el = RR.element(contact_branch="far", stroke={"from": 0.0, "to": -0.3}, points=points)
    res = synthesize(el)
    ph = res.slip.physical
    text = rolling_summary(res)
    assert "nan" not in text.lower()
    if math.isfinite(ph.slip):
        assert ph.samples >= 2 and ph.rolled > 0 and ph.end < ph.start
    else:
        assert ph.reason and ph.reason in text


def _geneva_slip_mp(el: Geneva, upto: float) -> mpmath.mpf:
    """∫ from −φ0 to ``upto`` of ρ_eff·|ω_pi|·sin²ψ (derived R_n, b = a/2, deformed radius; no
    external moment: M changes sign only at u = 0), 30 digits, written from the notes."""
    with mpmath.workdps(30):
        z = el.slots
        lam = mpmath.sin(mpmath.pi / z)
        A, rp, l_ = mpmath.mpf(el.center_distance), mpmath.mpf(el.roller_radius), mpmath.mpf(el.roller_length)
        r = A * lam
        w1 = mpmath.mpf(el.speed_rpm) * mpmath.pi / 30
        j2 = mpmath.mpf(el.load.wheel_inertia)
        fr = mpmath.mpf(el.load.journal_friction) * mpmath.mpf(el.load.journal_radius) * mpmath.mpf("1e-3")
        E, nu = mpmath.mpf(el.roller_material.E), mpmath.mpf(el.roller_material.poisson)
        phi0 = mpmath.pi / 2 - mpmath.pi / z

        def g(u):
            D = 1 - 2 * lam * mpmath.cos(u) + lam ** 2
            m = j2 * w1 ** 2 * (-lam * (1 - lam ** 2) * mpmath.sin(u) / D ** 2)
            if m == 0:
                return mpmath.mpf(0)
            rn = abs(m) / (A * mpmath.sqrt(D) * mpmath.mpf("1e-3") - mpmath.sign(m) * fr)
            a = mpmath.mpf("2.16") * mpmath.sqrt(rn * 2 * rp / (l_ * E))
            delta = 4 * rn / l_ * (1 - nu ** 2) / E * (mpmath.mpf("0.41") + mpmath.log(4 * rp / a))
            return (rp - delta) * r / rp * abs(mpmath.sin(u)) / mpmath.sqrt(D) * (a / 2 / rp) ** 2
        u = mpmath.mpf(upto)
        pts = [-phi0, 0, u] if u > 0 else [-phi0, u]
        return mpmath.quad(g, pts)


@pytest.mark.parametrize("n", [72, 3600])
def test_the_geneva_running_slip_path_is_as_accurate_as_its_total(n):
    el = _geneva(z=6, rpm=300.0 / math.pi, load=Load(wheel_inertia=0.05, external_moment=0.0,
                                                     journal_friction=0.05, journal_radius=15.0))
    con = contact(el, n, ContactModel())
    e = np.flatnonzero(con.engaged)
    total = con.slip_path_total
    assert con.slip_path[e[-1]] == pytest.approx(total, rel=1e-14)      # φ0 is a sample: the end
    picks = e[np.linspace(1, len(e) - 2, 7).astype(int)]
    for k in picks:
        ref = float(_geneva_slip_mp(el, float(con.u[k])))
        assert abs(con.slip_path[k] - ref) <= 4e-15 * total + 1e-18, (k, con.slip_path[k], ref)
    assert np.all(np.diff(con.slip_path[e]) >= 0.0)
