"""Simulation files (manual: "Use of GPS in Simulation", "Linear Battery Plugin"): the
components list's ANT02 entry, a world SDF's spherical coordinates, the battery plugin keys."""
