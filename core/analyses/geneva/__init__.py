"""Geneva drives (external, radial entry) after the second paper, corrected as in ``seeds/NOTES.md``.

:mod:`.kinematics` (wheel angle, ω, α, jerk in closed form), :mod:`.geometry` and :mod:`.relief`
(the exact wheel, locking disc, crank arm and roller; the relief radius that really clears),
:mod:`.clearance` (the locking clearance checked over a revolution), :mod:`.contact` (normal
force, Hertz contact, slip and Archard wear), :mod:`.torque` (the crank's driving torque) and
:mod:`.report` (the summary text and the CSV table).
"""
