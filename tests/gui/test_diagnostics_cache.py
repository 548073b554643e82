"""The diagnostics panel shows each result's summary computed once (issue 26 item 6): a refresh
after an edit of another element, an undo or a redo that brings a cached result back, shows the
same text without classifying the outputs again; the text is what the core's summary says."""
from __future__ import annotations

from mechsketch.core import ReplaceElement, Scene, load_scene
from mechsketch.core.analyses import classify as classify_mod
from mechsketch.gui.controller import SceneController
from mechsketch.gui.panels.diagnostics import DiagnosticsPanel, SummaryCache, diagnostics_lines
from mechsketch.resources import example_path


def _two_linkages() -> Scene:
    a = load_scene(example_path("fourbar_crank_rocker")).elements[0]
    b = load_scene(example_path("slider_crank_offset")).elements[0]
    assert a.id != b.id
    return Scene((a, b))


def _count_classifications(monkeypatch) -> list[str]:
    calls: list[str] = []
    real = classify_mod.output_motions

    def counting(lk, plan, sol, full=None):
        calls.append(lk.id)
        return real(lk, plan, sol, full)

    monkeypatch.setattr(classify_mod, "output_motions", counting)
    return calls


def test_an_edit_of_one_linkage_classifies_only_that_one_and_undo_redo_classify_nothing(qtbot, monkeypatch):
    ctl = SceneController(_two_linkages())
    calls = _count_classifications(monkeypatch)
    panel = DiagnosticsPanel(ctl)
    qtbot.addWidget(panel)
    panel.show()
    qtbot.waitExposed(panel)
    first = panel.plain_text()
    a, b = (el.id for el in ctl.scene.elements)
    assert sorted(calls) == sorted([a, b])
    lk = ctl.scene.element(b)
    j = lk.joints[-1]
    ctl.push(ReplaceElement(lk.with_joint_moved(j.id, (j.at[0] + 2.0, j.at[1] + 1.0))), "move")
    edited = panel.plain_text()
    assert calls[2:] == [b] and edited != first
    ctl.undo_stack.undo()
    assert panel.plain_text() == first and calls[3:] == []
    ctl.undo_stack.redo()
    assert panel.plain_text() == edited and calls[3:] == []
    # what it shows is what the core's summaries say, computed afresh
    fresh = [line for _, line in diagnostics_lines(SceneController(ctl.scene))]
    shown = [line.strip() for line in panel.plain_text().splitlines() if line.strip()]
    untimed = lambda xs: [x for x in xs if " ms" not in x]  # noqa: E731 - the solve times differ
    assert untimed(shown) == untimed([x.strip() for x in fresh if x.strip()])


def test_the_cache_holds_the_last_results_of_each_element_by_identity():
    class Res:
        def __init__(self, text):
            self.text, self.asked = text, 0

        def summary(self):
            self.asked += 1
            return self.text

    cache = SummaryCache(keep=2)
    r1, r2, r3 = Res("one"), Res("two"), Res("three")
    assert [cache.summary("x", r) for r in (r1, r2, r1, r2)] == ["one", "two", "one", "two"]
    assert (r1.asked, r2.asked) == (1, 1)
    cache.summary("x", r3)              # r1 is the oldest: dropped
    assert cache.summary("x", r1) == "one" and r1.asked == 2
    twin = Res("one")                    # an equal but different result is asked again
    cache.summary("x", twin)
    assert twin.asked == 1
    cache.forget_others(["y"])
    cache.summary("x", r1)
    assert r1.asked == 3
