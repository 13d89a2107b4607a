"""The robot's configuration model, the engine every feature edits (see docs/develop.md)."""
