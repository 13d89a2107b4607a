"""How commands show their results: one module per feature, each through the output module (cli/output.py)."""
