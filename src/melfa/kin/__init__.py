"""melfa.kin (being built)."""
