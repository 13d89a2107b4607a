"""`geometry_msgs` stand-in of the panther-ops test lab's Python image (see rclpy/__init__.py)."""
