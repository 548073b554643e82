"""Docked panels: properties, plots, diagnostics."""
