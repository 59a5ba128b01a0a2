"""What the tools share: summary.json / history.csv key names, Christiansen's equations."""
