"""Analyses of solved mechanisms, one sub-package per mechanism or concern.

- :mod:`.geneva` — Geneva drives after the second paper: kinematics, exact wheel geometry and
  relief, roller/slot contact and wear, crank torque, the report;
- :mod:`.rolling` — rolling levers after the third paper: exact, corrected and paper synthesis of
  the profiles (centrodes), slip measures, the drive, the report;
- :mod:`.forces` — kinetostatics of linkages by Assur groups, and its report;
- :mod:`.parts` — cut-ready parts: outlines built from each element, checked, laid out.

Shared by them, at this level: :mod:`.contour` (closed chains of exact lines and arcs),
:mod:`.biarc` (biarc fitting of smooth curves), :mod:`.centrodes` (instant centres of linkage
links), :mod:`.classify` (a linkage's kind, outputs, strokes), :mod:`.linkage_report` (the linkage
summary text) and :mod:`.table` (the column tables that CSV files and plots read).
"""
