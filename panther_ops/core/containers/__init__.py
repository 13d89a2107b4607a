"""The shared engine: containers read through docker (logs, times), and scripts run in the
driver container with one command per robot (driver_exec, exec_output: E-stop, teleop, GPS)."""
