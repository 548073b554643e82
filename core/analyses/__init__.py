"""Analyses built on the solver: Geneva drives, centrodes, rolling levers, contact."""
