"""panther-ops: fleet operations and configuration for Husarion Panther robots."""

from __future__ import annotations

__version__ = "0.1.0"
