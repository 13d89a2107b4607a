"""The shared engine: inventory, targets, the fleet runner, the change pipeline, history."""
