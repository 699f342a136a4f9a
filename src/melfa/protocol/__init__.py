"""melfa.protocol (being built)."""
