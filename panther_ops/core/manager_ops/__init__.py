"""Feature: the runtime manager on robots (deploy, bundle, status, lights test)."""
