"""OS reimage: flash and verify a robot's card on this machine, back up what makes a robot itself."""
