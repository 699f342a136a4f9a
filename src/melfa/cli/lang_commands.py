"""`melfa check` and `melfa fmt` (being built)."""
