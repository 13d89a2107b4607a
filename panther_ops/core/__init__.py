"""Domain logic: readers, pure planners and the executors of their steps. No typer, no rich."""
