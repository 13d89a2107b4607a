"""Side effects: every remote (or local stand-in) action goes through a Transport."""
