"""Non-circular gear pairs: pitch curves (exact centrodes of the relative motion), checks, kinematics."""
