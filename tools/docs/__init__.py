"""The tables of README.md and docs/, regenerated from the program's own runs."""
