"""melfa.sim (being built)."""
