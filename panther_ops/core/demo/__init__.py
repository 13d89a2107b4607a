"""The embedded demo fleet: local robots that are directories, with the features' recorded answers."""
