"""melfa.robot (being built)."""
