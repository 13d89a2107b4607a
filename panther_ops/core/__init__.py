"""Domain logic: readers, pure planners and appliers. No typer, no rich."""
