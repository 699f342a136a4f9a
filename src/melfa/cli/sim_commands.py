"""`melfa sim` (being built)."""
