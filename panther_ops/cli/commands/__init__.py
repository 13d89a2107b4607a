"""One module per command group; each imports the core lazily, inside its commands."""
