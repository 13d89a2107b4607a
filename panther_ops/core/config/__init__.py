"""Feature: a robot's configuration (compose.yaml, launch arguments, config files, push/pull).

Other features build on it (the driver, the manager, shutdown): importing it is declared."""
