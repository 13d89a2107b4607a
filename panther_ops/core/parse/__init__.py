"""Parsers of single values every file kind and command option shares: numbers, ports, ids
(ASCII digits only) and ROS names (topics, services, namespaces)."""
