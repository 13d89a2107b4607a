"""Feature: remote control (the manual's "Remote Control"): the E-stop, keyboard teleoperation, the
User Computer behind the robot and the WebUI snap on it."""
