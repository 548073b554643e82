"""Context help (Qt-free): a page for each canvas tool and each dock, the keys the canvas reads
itself, and the shortcuts page made from the window's actions.

F1 over a dock opens ``dock/NAME``; over the canvas ``tool/NAME`` of the active tool. Each page
ends with a link into the README's section that says more (``manual:/readme/SLUG.md``; the tests
check that every link lands on a page).
"""
from __future__ import annotations

from dataclasses import dataclass

from .manual import Page


@dataclass(frozen=True)
class Topic:
    """What a tool or dock does, how to use it, and the README section for more."""

    title: str
    text: str
    more: str          # slug of the README page that says more
    picture: str = ""  # a picture of it at work (in the manual's pictures/)


def _more(slug: str, what: str) -> str:
    return f"\n\nMore: [{what}](manual:/{slug}.md) · [Keyboard shortcuts](manual:/shortcuts.md)\n"


APP = "readme/the-desktop-app"
DRAW = "readme/drawing-geneva-drives-rolling-levers-and-every-dyad-from-file-new"
GENEVA = "readme/geneva-drives-and-rolling-levers-in-the-app"
DIMS = "readme/drivers-motion-laws-and-dimensions"
FORCES = "readme/forces-analyze-forces"
STUDY = "readme/the-study-dock-tolerances-clearances-optimisation"
DESIGN = "readme/the-design-dock-synthesis-and-design-from-requirements"

TOOLS: dict[str, Topic] = {
    "select": Topic("Select (S)", "Click a joint, a link or an element to select it; Shift-click adds to the "
                    "selection; drag on empty space for a rubber band. **Drag a joint** to reshape the "
                    "linkage: the whole cycle is re-solved live and the release is one undo step. Drag the "
                    "crank to turn the input. A selected Geneva drive or rolling lever shows handles.", APP),
    "ground": Topic("Ground pivot (G)", "Click to place a pivot on the frame. With a linkage selected the "
                    "pivot joins it; otherwise a new linkage starts. Snapping (F9) puts it on the grid or "
                    "on a joint.", APP),
    "crank": Topic("Crank (C)", "Click a ground pivot, then the crank tip: the crank becomes the driver "
                   "(speed and direction in Properties).", DIMS),
    "rrr": Topic("RRR dyad (R)", "Click the first known joint, the second known joint, then place the inner "
                 "joint. The preview shows the two links; a placement the dyad cannot reach is explained "
                 "in the status bar.", APP),
    "rrp": Topic("Slider dyad RRP (P)", "Click the known joint, then the guide's start (on a moving link, or "
                 "empty space for the frame), then the slider pin.", APP),
    "rpr": Topic("RPR dyad (I)", "Click the joint the block pivots on, then the pivot of the slotted bar.", APP),
    "prp": Topic("PRP dyad (Y)", "Click guide 1's start (a moving link, or empty space for the frame), the "
                 "pin, then guide 2's start.", DRAW, "tool_prp_placing.png"),
    "rpp": Topic("RPP dyad (X)", "Click the joint the block pivots on, the guide's start (a moving link, "
                 "or empty space for the frame), then the yoke point (a Scotch yoke).", DRAW),
    "coupler": Topic("Coupler point (K)", "Click on a moving link to add a point to it; T traces the "
                     "selected joints' paths (coupler curves).", APP),
    "delete": Topic("Delete (D)", "Click a joint or a link to delete it (one undo step). Del deletes the "
                    "selection with any tool.", APP),
    "measure": Topic("Measure (M)", "Click two points (joints snap): the distance and the angle are shown "
                     "in the status bar.", APP),
    "geneva": Topic("Geneva drive (W)", "Click the crank centre, then the wheel centre (this sets the centre "
                    "distance A). Keys 3-9 choose the number of slots, while placing and for the drive just "
                    "placed. Every other size is scaled to A.", DRAW, "tool_geneva_placing.png"),
    "rolling": Topic("Rolling lever (O)", "Seven clicks: the lever circle's centre and a point on it, the "
                     "pin, the rocker pivot, the slider circle's centre and a point on it, and a point on "
                     "the slider axis. The exact profiles are synthesised.", DRAW, "tool_rolling_placing.png"),
    "insert": Topic("Insert", "Click where the inserted scene's centre goes (Examples › Insert); its ids are "
                    "renamed where they are taken. Esc cancels.", DRAW),
    "underlay": Topic("Placing an underlay", "Click the first of two points of known distance on the underlay "
                      "(its vertices snap), then the second, and type the distance between them (in the length "
                      "unit of the preferences): the underlay is scaled about the first point. Esc keeps it as "
                      "it is. View › Underlays also moves, hides and removes it.",
                      "readme/underlays-clipboard-and-dropped-files", "underlay.png"),
}

DOCKS: dict[str, Topic] = {
    "properties": Topic("Properties", "The selected joint's coordinates or slider axis, the selected link's "
                        "dimensions, mass and loads, the driver (law, speed, direction or stroke), the "
                        "assembly modes with Flip, and the linkage's Dimensions table. Type a value and "
                        "press Enter: every edit is one undo step; a value the linkage cannot take is "
                        "refused with the reason.", DIMS),
    "diagnostics": Topic("Diagnostics", "The text of `mechsketch analyze --summary` for each element: kind, "
                         "mobility, groups and modes, reachable ranges, dead points, transmission angle, the "
                         "solve's time and residual; with masses or loads the forces summary of "
                         "`analyze --forces --summary`.", FORCES),
    "plots": Topic("Plots", "The selected joint's position, velocity and acceleration, a link's angle, ω "
                   "and ε, the transmission angles, and the driving torque, against the input. Gaps are "
                   "poses that cannot be assembled; the dashed cursor follows the animation; click a plot "
                   "to jump there.", APP, "forces_torque.png"),
    "study": Topic("Study", "Tolerance and pin-clearance Monte Carlo, or optimisation, of a linkage. Tick "
                   "the variables (the Dimensions table's rows and the frame's pivots) and give each a ± "
                   "tolerance or a range; give each pin an ISO 286 fit; press **Run** (Ctrl+Enter): it runs "
                   "on a worker thread with progress and **Cancel**. The band of the traced point is drawn "
                   "on the canvas (magnified, labelled), with the histogram of the deviation and the "
                   "sensitivity bars; an optimisation shows its Pareto front: click a point to preview "
                   "the variant, **Apply** or **Add as new element** (one undo step).", STUDY, "study.png"),
    "design": Topic("Design", "A linkage from what it must do: a **path** (click points on the canvas, draw "
                    "it freehand, read a CSV or pick an underlay's polyline), **poses** (press at a point, "
                    "drag along its angle) or a **function** (input–output pairs). **Design** runs on a "
                    "worker thread with progress and **Cancel**; the candidates are listed with a "
                    "thumbnail and their numbers, the chosen one moves on the canvas, **Insert** adds it "
                    "as an ordinary linkage (one undo step). The Geneva, Rolling lever and Gears pages "
                    "design those from requirements, with the report and what to relax when refused.",
                    DESIGN, "design.png"),
}

#: keys the canvas reads itself (no menu action): (keys, what)
CANVAS_KEYS: list[tuple[str, str]] = [
    ("Mouse wheel", "zoom to the cursor"),
    ("Middle drag, Space + drag", "pan"),
    ("Shift + click", "add to the selection"),
    ("Esc", "cancel what the tool is doing"),
    ("3 … 9", "Geneva tool: the number of slots"),
    ("F1", "help on what is under the pointer: the dock, or the active tool on the canvas"),
]


def topic_page(kind: str, name: str) -> Page:
    """The page of a tool or dock (``kind`` "tool" or "dock"); an unknown one gets a short page
    pointing into the manual."""
    table = TOOLS if kind == "tool" else DOCKS
    topic = table.get(name)
    if topic is None:
        title = name.replace("_", " ").capitalize()
        return Page(f"{kind}/{name}", title, f"# {title}\n\nNo help page for this {kind} yet."
                    + _more(APP, "The desktop app"))
    picture = f"\n\n![{topic.title}](pictures/{topic.picture})" if topic.picture else ""
    return Page(f"{kind}/{name}", topic.title,
                f"# {topic.title}\n\n{topic.text}{picture}" + _more(topic.more, "the manual"))


def shortcuts_page(rows: list[tuple[str, str, str]]) -> Page:
    """The shortcuts page from ``rows`` (menu, command, keys) of the window's actions, then the
    canvas's own keys."""
    lines = ["# Keyboard shortcuts", "",
             "Window shortcuts work wherever the focus is, except that a text field being edited "
             "keeps the keys it types.", "", "| menu | command | keys |", "|---|---|---|"]
    lines += [f"| {_cell(menu)} | {_cell(what)} | {_cell(keys)} |" for menu, what, keys in rows]
    lines += ["", "## On the canvas", "", "| keys | what |", "|---|---|"]
    lines += [f"| {_cell(k)} | {_cell(w)} |" for k, w in CANVAS_KEYS]
    return Page("shortcuts", "Keyboard shortcuts", "\n".join(lines) + "\n")


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("&", "")
