"""Keyboard teleoperation of one robot from this terminal (`panther-ops teleop`)."""

from __future__ import annotations
