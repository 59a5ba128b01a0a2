"""Pictures and plots of a run, and the check that VTK reads its frames."""
