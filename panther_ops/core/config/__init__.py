"""Feature: `panther-ops config` (set/unset/get of launch arguments and controller limits,
push/pull of configuration files). A feature like the others: it edits the robot's
configuration model (`core.robot`), which the other features share; nothing in core imports it."""
