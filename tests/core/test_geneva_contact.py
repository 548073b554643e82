"""Roller/slot contact and wear (Stetsiv, corrected) against the notes' default-scene table, an
independent re-derivation from positions and finite differences, and scipy quadrature."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from mechsketch.core.analyses.geneva.contact import breakpoints, ContactConstants, slip_path_gauss
from mechsketch.core.analyses.geneva.contact import contact
from mechsketch.core.model.geneva import ContactModel, Drawing, Geneva, Load, Material

RPM10 = 300.0 / math.pi  # ω1 = 10 rad/s
PAPER = ContactModel(normal_force="paper")


def default(**kw) -> Geneva:
    kw.setdefault("speed_rpm", RPM10)
    return Geneva("g", kw.pop("z", 6), 100.0, 8.0, drawing=Drawing(wheel_bore_radius=1.0), **kw)


def test_notes_default_scene_table():
    """seeds/NOTES.md, "Default scene values" (paper's R_n)."""
    el = default()
    c = contact(el, 3600, PAPER)
    e = c.engaged
    u = c.u[e]
    assert c.Rn[e][np.argmin(np.abs(u))] == 0.0  # R_n = 0 at φ = 0
    assert round(c.Rn[e][0], 1) == 32.8  # at entry (φ = −60° is a sample)
    assert round(c.Rn_max, 1) == 116.4 and round(c.phi_Rn_max, 2) == 0.35
    k = np.nanargmax(c.Rn_derived)
    assert round(c.Rn_derived[k], 1) == 121.2 and round(c.phi[k], 2) == -0.35
    assert round(np.nanmax(c.strip_width) * 1e3) == 64  # µm
    assert round(np.nanmax(c.deformation) * 1e3, 2) == 1.34  # µm
    assert c.rolling_ratio[e][0] == pytest.approx(-6.25, rel=1e-12)  # |ω_pi| = r/r_p at entry
    assert round(c.slip_path_total * 1e3, 3) == 0.762  # µm
    assert round(c.slip_path_total_trapezoid * 1e3, 3) == 0.762
    assert round(c.wear_invariant_max / 1e6, 1) == 9.6  # N·min/m
    assert round(c.pressure_max) == 231  # MPa
    acc, brk = (u < -0.01), (u > 0.01)
    ratio = np.full(u.shape, np.nan)
    ratio[acc | brk] = c.Rn_derived[e][acc | brk] / c.Rn_paper[e][acc | brk]
    assert 0.026 <= ratio[acc].min() - 1 and ratio[acc].max() - 1 <= 0.046 + 5e-4
    assert 0.009 - 5e-4 <= ratio[brk].min() - 1 and ratio[brk].max() - 1 <= 0.015
    # B2: the paper's "half-length" is the full Hertz width for steel: a/(2b) = 1.0033
    loaded = e & (c.Rn > 0)
    assert np.allclose(c.strip_width[loaded] / (2 * c.hertz_half_width[loaded]), 1.0033, atol=1e-4)


def reference_integrand(el: Geneva, model: ContactModel):
    """The slip integrand g(u) = ρ_eff |ω_pi| sin²ψ (mm/rad) and p̄ (MPa), re-derived from the notes
    with positions and forces, independently of the module's formulas."""
    a, rp, length, z = el.center_distance, el.roller_radius, el.roller_length, el.slots
    r = el.crank_radius
    j2, mext = el.load.wheel_inertia, el.load.external_moment
    f, r02 = el.load.journal_friction, el.load.journal_radius
    e1, n1, e2, n2 = el.roller_material.E, el.roller_material.poisson, el.wheel_material.E, el.wheel_material.poisson
    w = el.omega1

    def rho(u):  # |O2 P| from the positions
        return math.hypot(r * math.cos(u) - a, r * math.sin(u))

    def theta(u):  # wheel angle from the positions (indexing sense)
        return math.atan2(r * math.sin(u), a - r * math.cos(u))

    def fields(u):
        h = 1e-4
        eps = (theta(u + h) - 2 * theta(u) + theta(u - h)) / h ** 2  # ε2/ω1², by finite differences
        m = j2 * w * w * eps + mext
        if model.normal_force == "paper":
            rn = math.sin(math.pi / z) * abs(m) / (r * 1e-3 * math.sqrt(1 - 2 * (r / a) * math.cos(u) + (r / a) ** 2) + f * r02 * 1e-3)
        else:  # moment balance about O2: R_n·ρ = |M| + (friction opposing the rotation, helping while braking)
            rn = abs(m) / (rho(u) * 1e-3 - math.copysign(f * r02 * 1e-3, m)) if m else 0.0
        estar = 1 / ((1 - n1 ** 2) / e1 + (1 - n2 ** 2) / e2)
        b_h = math.sqrt(4 * rn * rp / (math.pi * length * estar))
        a_p = 2.16 * math.sqrt(rn * 2 * rp / (length * 2 * e1 * e2 / (e1 + e2)))
        delta = 4 * rn / length * (1 - n1 ** 2) / e1 * (0.41 + math.log(4 * rp / a_p)) if rn > 0 else 0.0
        b = {"paper_half": a_p / 2, "hertz": b_h, "paper_full": a_p}[model.half_width]
        reff = rp - delta if model.slip_radius == "deformed" else rp
        drho = (rho(u + 1e-6) - rho(u - 1e-6)) / 2e-6  # eq. (5) as |dρ/dφ|/r_p
        g = reff * abs(drho) / rp * (b / rp) ** 2
        pbar = rn / (2 * b_h * length) if rn > 0 else 0.0
        return g, pbar, m

    return fields


@pytest.mark.parametrize("z,model,mext,rpm", [
    (6, PAPER, 0.0, RPM10),
    (6, ContactModel(), 0.0, RPM10),
    (3, ContactModel(half_width="hertz", slip_radius="undeformed"), 0.0, RPM10),
    (4, ContactModel(half_width="paper_full"), 2.0, RPM10),
    (8, ContactModel(), -0.4, -2 * RPM10),
])
def test_slip_path_and_wear_against_scipy_with_breaks(z, model, mext, rpm):
    el = default(z=z, speed_rpm=rpm, load=Load(external_moment=mext, journal_radius=3.0 if z == 3 else 15.0))
    fields = reference_integrand(el, model)
    br = breakpoints(ContactConstants(el, model))
    if mext:  # the moment changes sign away from φ = 0, and the module found where
        inner = br[(np.abs(br) > 1e-9) & (np.abs(br) < el.phi0 - 1e-9)]
        assert inner.size >= 1
        for x in inner:
            assert abs(fields(x)[2]) < 1e-6 * abs(el.load.wheel_inertia * el.omega1 ** 2)
    ls = sum(integrate.quad(lambda u: fields(u)[0], lo, hi, epsabs=0, epsrel=1e-9, limit=200)[0]
             for lo, hi in zip(br[:-1], br[1:]))
    c = contact(el, 3600, model)
    assert c.slip_path_total == pytest.approx(ls, rel=1e-7)
    assert c.slip_path_total_trapezoid == pytest.approx(ls, rel=2e-6)
    # the reference differentiates positions numerically (≈1e-8); the two Gauss rules agree far better
    assert slip_path_gauss(el, model, 96) == pytest.approx(ls, rel=1e-7)
    assert slip_path_gauss(el, model, 96) == pytest.approx(c.slip_path_total, rel=1e-10)
    # Archard: k ∫ p̄ dL_s on each flank, slip path in metres
    drive = brake = 0.0
    for lo, hi in zip(br[:-1], br[1:]):
        part = integrate.quad(lambda u: fields(u)[0] * fields(u)[1], lo, hi, epsrel=1e-10, limit=200)[0]
        if fields(0.5 * (lo + hi))[2] > 0:
            drive += part
        else:
            brake += part
    k = el.wear.specific_wear_rate
    assert c.life.depth_drive == pytest.approx(k * drive * 1e-3, rel=1e-6)
    assert c.life.depth_brake == pytest.approx(k * brake * 1e-3, rel=1e-6)
    worst = max(c.life.depth_drive, c.life.depth_brake)
    assert c.life.slot_cycles == pytest.approx(z * el.wear.allowed_wear / worst)
    assert c.life.roller_cycles == pytest.approx(el.wear.allowed_wear / (c.life.depth_drive + c.life.depth_brake))
    assert c.life.hours == pytest.approx(c.life.cycles / (60 * abs(rpm)))


def test_sampled_columns_against_the_independent_fields_and_eq5_against_drho():
    el = default(load=Load(external_moment=0.7))
    model = ContactModel()
    fields = reference_integrand(el, model)
    c = contact(el, 720, model)
    e = np.nonzero(c.engaged)[0]
    for k in e[::7]:
        g, pbar, m = fields(c.u[k])
        assert c.moment[k] == pytest.approx(m, rel=1e-6, abs=1e-9)
        assert c.slip_speed[k] == pytest.approx(g * abs(el.omega1), rel=1e-5, abs=1e-15)
        assert c.mean_pressure[k] == pytest.approx(pbar, rel=1e-6, abs=1e-12)
        # eq. (5), robust form, against the derivative of the roller-centre radius ρ(φ) = |O2 P|
        r, a = el.crank_radius, el.center_distance
        rho = lambda u: math.hypot(r * math.cos(u) - a, r * math.sin(u))  # noqa: E731
        drho = (rho(c.u[k] + 1e-6) - rho(c.u[k] - 1e-6)) / 2e-6
        assert c.rolling_ratio[k] == pytest.approx(drho / el.roller_radius, rel=1e-7, abs=1e-9)
    assert np.all(np.isnan(c.Rn[~c.engaged])) and np.all(np.isnan(c.slip_path[~c.engaged]))
    assert np.all(np.diff(c.slip_path[e]) >= 0) and c.slip_path[e][0] == 0.0
    assert c.slip_path[e][-1] == pytest.approx(c.slip_path_total, rel=1e-14)  # φ0 is a sample (issue 13, item 11)
    assert c.slip_path_total_trapezoid == pytest.approx(c.slip_path_total, rel=1e-4)


def test_robust_rolling_ratio_where_the_printed_form_cancels():
    el = default()
    lam = el.lam
    c = contact(el, 3600, ContactModel())
    u = c.u[c.engaged]
    w = c.rolling_ratio[c.engaged]
    d = 1 - 2 * lam * np.cos(u) + lam * lam
    printed = (el.crank_radius / el.roller_radius) * np.sqrt(1 - (np.cos(u) - lam) ** 2 / d)
    away = np.abs(u) > 0.05
    assert np.allclose(np.abs(w[away]), printed[away], rtol=1e-9)
    at0 = np.argmin(np.abs(u))
    assert u[at0] == 0.0 and w[at0] == 0.0 and printed[at0] > 1e-8  # the printed form gives ~9e-8


def test_two_materials_hertz_half_width():
    bronze = Material(E=110000.0, poisson=0.34)
    el = default(wheel_material=bronze)
    c = contact(el, 1200, ContactModel())
    estar = 1 / ((1 - 0.3 ** 2) / 210000.0 + (1 - 0.34 ** 2) / 110000.0)
    e = c.engaged
    assert np.allclose(c.hertz_half_width[e], np.sqrt(4 * c.Rn[e] * 8.0 / (math.pi * 10.0 * estar)), rtol=1e-13)
    epair = 2 * 210000.0 * 110000.0 / 320000.0
    assert np.allclose(c.strip_width[e], 2.16 * np.sqrt(c.Rn[e] * 16.0 / (10.0 * epair)), rtol=1e-13)
    steel = contact(default(), 1200, ContactModel())
    assert np.nanmax(c.contact_pressure) < np.nanmax(steel.contact_pressure)  # softer wheel, lower pressure


def test_trapezoid_converges_at_second_order_with_breaks():
    el = default(z=4, load=Load(external_moment=3.0))
    ref = slip_path_gauss(el, ContactModel(), 200)
    errs = [abs(contact(el, n, ContactModel()).slip_path_total_trapezoid - ref) for n in (400, 800, 1600, 3200)]
    rates = [errs[i] / errs[i + 1] for i in range(3)]
    assert all(3.3 < q < 4.7 for q in rates), (errs, rates)


def test_clockwise_crank_gives_the_mirror_image():
    ccw = contact(default(z=5), 1000, ContactModel())
    cw = contact(default(z=5, speed_rpm=-RPM10), 1000, ContactModel())
    for name in ("Rn", "Rn_paper", "moment", "slip_path", "slip_speed", "contact_pressure", "rolling_ratio"):
        assert np.allclose(getattr(cw, name), getattr(ccw, name), equal_nan=True, rtol=1e-12, atol=1e-15), name
    assert np.allclose(cw.phi, -ccw.phi)
    assert cw.phi_Rn_max == pytest.approx(-ccw.phi_Rn_max)


def test_no_load_gives_zero_force_and_no_nan_warnings():
    el = default(load=Load(wheel_inertia=0.0, external_moment=0.0))
    with np.errstate(all="raise"):
        c = contact(el, 360, ContactModel())
    e = c.engaged
    assert np.all(c.Rn[e] == 0) and np.all(c.deformation[e] == 0) and c.slip_path_total == 0.0 == c.slip_path_total_trapezoid
    assert np.all(np.isnan(c.wear_invariant)) and math.isinf(c.life.cycles) and c.Rn_max == 0.0


def test_every_assumption_is_stated():
    text = " ".join(contact(default(), 100, ContactModel(half_width="hertz", slip_radius="undeformed")).assumptions)
    for words in ("λ = r/A = sin(π/z)", "derived from the wheel's moment balance", "the Hertz half-width b",
                  "undeformed radius r_p", "N·min/m", "Archard", "upper bound", "spurious ω1"):
        assert words in text
    text = " ".join(contact(default(), 100, PAPER).assumptions)
    assert "eq. (3) as printed" in text and "a_paper/2" in text and "deformed radius r_p − Δ" in text


@pytest.mark.parametrize("n", [1, 2, 3, 8, 48, 96])
def test_gauss_legendre_rule_against_mpmath(n):
    """The rule the contact integrals use (Golub–Welsch plus a Newton step, not numpy.polynomial):
    nodes and weights against mpmath's at 40 digits, and exact for x^(2n−2)."""
    import mpmath

    from mechsketch.core.analyses.geneva.contact import _gauss

    x, w = _gauss.__wrapped__(n)
    with mpmath.workdps(40):
        xs, ws = [], []
        for k in range(n)[::-1]:  # ascending: Newton from Tricomi's estimate of the k-th largest root
            t = mpmath.cos(mpmath.pi * (4 * k + 3) / (4 * n + 2))
            for _ in range(10):
                dp = n * (t * mpmath.legendre(n, t) - mpmath.legendre(n - 1, t)) / (t * t - 1)
                t -= mpmath.legendre(n, t) / dp
            xs.append(t)
            ws.append(2 / ((1 - t * t) * dp ** 2))
    assert all(b - a > 1e-3 / n for a, b in zip(xs, xs[1:]))  # n distinct roots
    assert np.abs(x - np.array([float(t) for t in xs])).max() <= 4e-16
    assert np.abs(w / np.array([float(v) for v in ws]) - 1).max() <= 2e-13
    assert float(np.sum(w * x ** (2 * n - 2))) == pytest.approx(2 / (2 * n - 1), rel=1e-14)
