"""Parsers of single values every file kind and command option shares: numbers, ports, ids
(ASCII digits only), ROS names (topics, services, namespaces) and the shell words of a
command line (compose's ``command:``, a container's ``Cmd``, a ``bash -c`` script)."""
