"""Composition: the inventory's desired state applied across the features (launch arguments, controller, image, GPS)."""
