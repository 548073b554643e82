"""Rolling levers after the third paper (Dvornikov & Maksimova), corrected as in ``seeds/NOTES.md``.

:mod:`.geometry` (the lever's pairs D and E, poses), :mod:`.exact` (the exact ODE of the rolling
motion and its working range), :mod:`.paper` (the paper's compass construction, for comparison),
:mod:`.slip` (slip measures of synthesised profiles), :mod:`.drive` (crank and coupler that drive
the lever), :mod:`.synthesis` (the three methods behind one call) and :mod:`.report`.
"""
