"""Structural analysis (Assur groups) and the vectorised closed-form kinematic solver."""
