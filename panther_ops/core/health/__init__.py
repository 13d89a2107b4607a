"""Feature: what each robot is and how it is doing (status, doctor)."""
