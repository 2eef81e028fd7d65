"""Pytest configuration: the helpers in sim.py share compiled functions across the whole session."""
