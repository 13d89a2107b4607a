"""The shared engine: containers read through docker (logs, times)."""
