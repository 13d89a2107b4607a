"""The shared engine: YAML documents edited round-trip, their nodes, rendering and diffs."""
