"""melfa.link (being built)."""
