"""View overlays, the centrodes view and File -> Export Animation, driven through the app's menus."""
from __future__ import annotations

import math

import ezdxf
import numpy as np
import pytest
from PIL import Image
from PySide6.QtCore import QPointF

from app_fakes import open_example, shell  # noqa: F401 - fixture
from mechsketch.core.solver import plan as plan_mod


def _menu(window, title: str):
    return next(a.menu() for a in window.menuBar().actions() if a.text().replace("&", "") == title)


def test_velocity_and_acceleration_arrows_to_a_stated_scale(shell):
    parts, ctl, view = open_example(shell, "fourbar_crank_rocker")
    ctl.set_selection([("fourbar", "joint", "C")])
    act = view.extras.actions["vectors"]
    assert act in _menu(parts.window, "View").actions()
    act.trigger()
    ctl.set_frame(40)
    item = view.extras.overlays.items["vectors"]
    (rec, legend) = item.records
    sol = ctl.result("fourbar").solution
    v, a = sol.velocity("C")[40], sol.acceleration("C")[40]
    text = legend["text"]
    sv = float(text.split("1 mm ≙ ")[1].split(" mm/s")[0])
    sa = float(text.split("1 mm ≙ ")[2].split(" mm/s²")[0])
    at = sol.position("C")[40]
    np.testing.assert_allclose(np.subtract(rec["v_tip"], at) * sv, v, rtol=1e-9)
    np.testing.assert_allclose(np.subtract(rec["a_tip"], at) * sa, a, rtol=1e-9)
    # the scale is a 1-2-5 number that keeps the largest arrow of the cycle near 30 % of the size
    vmax = np.nanmax(np.linalg.norm(sol.velocity("C"), axis=1))
    assert str(sv)[0] in "125" and vmax / sv < 0.31 * 200


def test_instant_centres_and_transmission_angles_follow_the_frame_without_solving(shell, monkeypatch):
    parts, ctl, view = open_example(shell, "fourbar_crank_rocker")
    ctl.set_selection([("fourbar", "link", "coupler")])
    view.extras.actions["centres"].trigger()
    view.extras.actions["transmission"].trigger()
    sol = ctl.result("fourbar").solution

    def boom(*a, **k):
        raise AssertionError("solved during playback")

    monkeypatch.setattr(plan_mod.Plan, "evaluate", boom)
    for k in (10, 100, 200):
        ctl.set_frame(k)
        recs = {r["label"]: r for r in view.extras.overlays.items["centres"].records if not r.get("far")}
        # Kennedy: I(coupler, ground) is where A-B and D-C meet
        a, b, c, d = (sol.position(j)[k] for j in "ABCD")
        e1, e2 = b - a, c - d
        s = ((d - a)[0] * e2[1] - (d - a)[1] * e2[0]) / (e1[0] * e2[1] - e1[1] * e2[0])
        if "I(coupler,ground)" in recs:
            np.testing.assert_allclose(recs["I(coupler,ground)"]["at"], a + s * e1, atol=1e-6)
        # relative to the crank and the rocker the centres are the joints they share
        np.testing.assert_allclose(recs["I(coupler,crank)"]["at"], b, atol=1e-6)
        np.testing.assert_allclose(recs["I(coupler,rocker)"]["at"], c, atol=1e-6)
        (mu,) = view.extras.overlays.items["transmission"].records
        u, w = b - c, d - c
        want = math.degrees(abs(math.atan2(u[0] * w[1] - u[1] * w[0], u @ w)))
        assert mu["mu"] == pytest.approx(want, abs=1e-9)
    view.grab()


def test_geneva_overlay_phase_force_and_most_loaded_place(shell):
    parts, ctl, view = open_example(shell, "geneva_z6")
    view.extras.actions["geneva"].trigger()
    res = ctl.element_result("indexer")
    kin, con = res.kinematics, res.contact
    k_dwell = int(np.flatnonzero(~kin.engaged)[0])
    k_max = int(np.nanargmax(con.Rn))
    total = ctl.sample_count()
    ctl.set_frame(k_dwell * total // res.n_frames)
    (rec,) = view.extras.overlays.items["geneva"].records
    assert "dwell" in rec["phase"] and rec["force"] is None
    ctl.set_frame(round(k_max * total / res.n_frames))
    (rec,) = view.extras.overlays.items["geneva"].records
    k = round(round(k_max * total / res.n_frames) * res.n_frames / total) % res.n_frames
    assert "indexing" in rec["phase"]
    scale = float(rec["scale"].split("≙ ")[1].split(" N")[0])
    tail, tip = np.asarray(rec["force"][0]), np.asarray(rec["force"][1])
    assert np.linalg.norm(tip - tail) * scale == pytest.approx(con.Rn[k], rel=1e-9)
    # the force on the roller is normal to the slot (perpendicular to wheel centre -> roller centre)
    el = res.element
    rho = res.crank_rotation[k]
    roller = np.asarray(el.crank_center) + el.crank_radius * np.array([math.cos(rho), math.sin(rho)])
    radial = roller - np.asarray(el.wheel_center)
    assert abs(np.dot(tip - tail, radial)) < 1e-9 * np.linalg.norm(tip - tail) * np.linalg.norm(radial)
    assert np.linalg.norm(tip - roller) == pytest.approx(el.roller_radius)      # drawn at the contact
    assert len(rec["loaded"]) == 6 and "Rn max" in rec["loaded_text"]
    # at the sample of the maximum the mark on one slot is the contact point itself
    assert min(np.linalg.norm(np.asarray(p) - tip) for p in rec["loaded"]) < 1e-6
    view.grab()


def test_centrodes_view_rolls_and_exports_csv_and_dxf(shell, tmp_path):
    parts, ctl, view = open_example(shell, "fourbar_coupler_centrodes")
    ctl.set_selection([("fourbar", "link", "coupler")])
    view.extras.actions["centrodes"].trigger()
    cv = view.extras.overlays.centrodes
    item = cv.item
    assert item is not None and len(item.runs) == 2 and len(item.break_marks()) == 4   # two translations
    c = item.c
    for k in (30, 150, 300):
        ctl.set_frame(k)
        if not item.ok[k]:
            continue
        # the moving centrode, carried by the coupler, touches the fixed one at the instant centre
        t = item.moving.transform()
        p = c.p[k]
        x = t.map(QPointF(float(p[0]), float(p[1])))
        assert (x.x(), x.y()) == pytest.approx(tuple(c.world[k]), abs=1e-7)
        assert item.contact() == pytest.approx(tuple(c.P[k]), abs=1e-7)
    d = parts.dialogs
    d.save_names.extend([str(tmp_path / "c.csv"), str(tmp_path / "c.dxf")])
    parts.window.canvas_menus.actions["export_centrodes_csv"].trigger()
    assert (tmp_path / "c.csv").read_text().startswith("input,P.x,P.y,p.x,p.y,valid")
    parts.window.canvas_menus.actions["export_centrodes_dxf"].trigger()
    doc = ezdxf.readfile(tmp_path / "c.dxf")
    assert not doc.audit().has_errors
    assert {e.dxf.layer for e in doc.modelspace().query("LWPOLYLINE")} == {"FIXED_CENTRODE", "MOVING_CENTRODE"}
    assert "max deviation" in d.infos[-1][1]
    # relative to a second selected link: the crank (they share B: both centrodes shrink to it)
    view.extras.actions["centrodes"].trigger()
    ctl.set_selection([("fourbar", "link", "coupler"), ("fourbar", "link", "crank")])
    view.extras.actions["centrodes"].trigger()
    assert cv.item.c.relative_to == "crank"


def test_centrodes_without_a_selected_link_explain_and_stay_off(shell):
    parts, ctl, view = open_example(shell, "fourbar_coupler_centrodes")
    said = []
    ctl.message.connect(said.append)
    ctl.set_selection([])
    view.extras.actions["centrodes"].trigger()
    assert "select a link first" in said[-1]
    assert view.extras.overlays.centrodes.item is None
    assert not view.extras.actions["centrodes"].isChecked()          # the switch went back off


@pytest.mark.parametrize("suffix", [".gif", ".mp4"])
def test_export_animation_writes_one_cycle_off_the_gui_thread(shell, qtbot, tmp_path, suffix):
    parts, ctl, view = open_example(shell, "geneva_z6")
    menus = parts.window.canvas_menus
    assert menus.actions["export_animation"] in _menu(parts.window, "File").actions()
    target = tmp_path / f"anim{suffix}"
    parts.dialogs.save_names.append(str(target))
    ctl.set_frame(17)
    done = []
    menus.exporter.finished.connect(done.append)
    menus.exporter.start(str(target), frames=12)
    assert menus.status.isVisible()
    qtbot.waitUntil(lambda: bool(done), timeout=30000)
    assert target.exists() and ctl.frame == 17 and not menus.exporter.busy
    if suffix == ".gif":
        img = Image.open(target)
        assert img.n_frames == 12 and img.size[0] % 16 == 0
        frames = []
        for i in (0, 6):
            img.seek(i)
            frames.append(np.asarray(img.convert("RGB"), dtype=int))
        assert np.abs(frames[0] - frames[1]).sum() > 0          # the wheel moved between the frames
    else:
        import imageio.v2 as imageio
        reader = imageio.get_reader(str(target), format="FFMPEG")
        assert reader.count_frames() == 12
        reader.close()
    assert "12 frames" in done[0]


def test_a_cancelled_export_writes_nothing(shell, qtbot, tmp_path):
    parts, ctl, view = open_example(shell, "fourbar_crank_rocker")
    menus = parts.window.canvas_menus
    target = tmp_path / "x.gif"
    said = []
    menus.exporter.cancelled.connect(said.append)
    menus.exporter.start(str(target), frames=150)
    menus.status.cancel_button.click()
    qtbot.waitUntil(lambda: bool(said), timeout=30000)
    assert not target.exists() and not list(tmp_path.glob("*x.gif*")) and "nothing was written" in said[0]
