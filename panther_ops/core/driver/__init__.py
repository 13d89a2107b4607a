"""Feature: the driver container (status, logs, restart, versions, update, restore-defaults)."""
